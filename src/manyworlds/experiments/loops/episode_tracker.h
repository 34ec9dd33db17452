// The one place episodes are counted, for training and evaluation alike:
// return, length, and success (core/success.h: the env's `success` info
// field above 0.5 at any step of the episode, Meta-World's and MTRL's rule).
#ifndef MANYWORLDS_EXPERIMENTS_LOOPS_EPISODE_TRACKER_H_
#define MANYWORLDS_EXPERIMENTS_LOOPS_EPISODE_TRACKER_H_

#include <cstdint>
#include <span>
#include <vector>

#include "manyworlds/core/success.h"

namespace manyworlds::experiments {

struct EpisodeRecord {
  int64_t env = 0;
  double episode_return = 0.0;
  int64_t length = 0;
  bool success = false;
};

class EpisodeTracker {
 public:
  // success_index: the `success` info field's index, or -1.
  EpisodeTracker(int64_t num_envs, int64_t info_size, int success_index);

  // Forgets env i's running episode (it starts a new one).
  void Restart(int64_t env);
  // With on, an episode also ends at its first success step (Meta-World's
  // terminate_on_success).
  void EndAtSuccess(bool on) { end_at_success_ = on; }
  // Accounts one step of every env; calls on_end(record) for each env whose
  // episode ended (terminated, truncated, or at success with EndAtSuccess),
  // in env order, then restarts it.
  template <class OnEnd>
  void Step(std::span<const float> rewards, std::span<const bool> terminated,
            std::span<const bool> truncated, std::span<const float> info, OnEnd&& on_end) {
    for (int64_t i = 0; i < static_cast<int64_t>(returns_.size()); ++i) {
      Accumulate(i, rewards[i], info);
      if (terminated[i] || truncated[i] || (end_at_success_ && successes_[i] != 0)) {
        on_end(EpisodeRecord{i, returns_[i], lengths_[i], successes_[i] != 0});
        Restart(i);
      }
    }
  }
  bool has_success() const { return success_index_ >= 0; }

 private:
  void Accumulate(int64_t env, float reward, std::span<const float> info);

  int64_t info_size_;
  int success_index_;
  bool end_at_success_ = false;
  std::vector<double> returns_;
  std::vector<int64_t> lengths_;
  std::vector<char> successes_;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_LOOPS_EPISODE_TRACKER_H_
