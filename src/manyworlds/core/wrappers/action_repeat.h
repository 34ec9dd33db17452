// ActionRepeat: each step applies the action `repeat` times to the inner env (dm_control's
// "frame skip", MTEnv's and dmc2gym's action repeat; 2 in MTEnv's DeepMind-Control suites) and
// returns the sum of the rewards and the last observation. It stops early when the inner
// episode ends (terminated or truncated), as dmc2gym does. The info is the last inner step's,
// except `success`, which is the largest of the repeated steps, so that a success inside a
// repeat is not lost. The episode limit counts the wrapper's steps: the inner env's limit
// divided by `repeat`, rounded up; SetMaxEpisodeSteps(n) gives the inner env n * repeat.
#ifndef MANYWORLDS_CORE_WRAPPERS_ACTION_REPEAT_H_
#define MANYWORLDS_CORE_WRAPPERS_ACTION_REPEAT_H_

#include <cstdint>
#include <memory>
#include <vector>

#include "manyworlds/core/wrapper.h"

namespace manyworlds {

class ActionRepeat : public Wrapper {
 public:
  static constexpr int64_t kMaxRepeat = 1000;

  // Throws ConfigError if repeat is outside [1, kMaxRepeat].
  ActionRepeat(std::unique_ptr<Env> inner, int64_t repeat);

  int64_t repeat() const { return repeat_; }
  void SetMaxEpisodeSteps(int64_t max_episode_steps) override;

 protected:
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  int64_t repeat_;
  int success_index_ = -1;
  std::vector<float> info_;  // scratch for a step's info
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_ACTION_REPEAT_H_
