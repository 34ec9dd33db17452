#include "manyworlds/experiments/loops/episode_tracker.h"

#include "manyworlds/core/success.h"

namespace manyworlds::experiments {

EpisodeTracker::EpisodeTracker(int64_t num_envs, int64_t info_size, int success_index)
    : info_size_(info_size),
      success_index_(success_index),
      returns_(num_envs, 0.0),
      lengths_(num_envs, 0),
      successes_(num_envs, 0) {}

void EpisodeTracker::Restart(int64_t env) {
  returns_[env] = 0.0;
  lengths_[env] = 0;
  successes_[env] = 0;
}

void EpisodeTracker::Accumulate(int64_t env, float reward, std::span<const float> info) {
  returns_[env] += reward;
  ++lengths_[env];
  if (success_index_ >= 0 && IsSuccess(info[env * info_size_ + success_index_])) {
    successes_[env] = 1;
  }
}

}  // namespace manyworlds::experiments
