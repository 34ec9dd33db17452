// Bernoulli multi-armed bandit (MTEnv's MTBanditEnv idea): each task is a
// vector of arm success probabilities.
//
//   action:   Discrete(n_arms), the arm to pull.
//   env_obs:  Box(0, 1, (n_arms + 1,)): one-hot of the last arm pulled, then
//             the last reward; all zeros after Reset.
//   task_obs: Box(0, 1, (n_arms,)): the arm probabilities (zeros if
//             hide_task).
//   reward:   Bernoulli(p[a]), drawn from the env generator.
//   end:      never terminates; truncated after `horizon` steps.
//   info:     regret = max(p) - p[a]; best_arm = 1 if a is an optimal arm.
//   task state params: {"probs": [n_arms numbers in [0, 1]]}, each drawn
//             U[0, 1] by the task generator.
//   options:  n_arms (int, 5, in [2, 10000]), horizon (int, 100, >= 1),
//             hide_task (bool, false).
#ifndef MANYWORLDS_CLASSIC_BANDIT_H_
#define MANYWORLDS_CLASSIC_BANDIT_H_

#include <cstdint>
#include <vector>

#include "manyworlds/core/env.h"

namespace manyworlds::classic {

class BanditEnv : public Env {
 public:
  static constexpr const char* kId = "bandit";

  struct Config {
    int64_t n_arms = 5;
    int64_t horizon = 100;
    bool hide_task = false;
  };

  // Throws ConfigError on an out-of-range option.
  explicit BanditEnv(const Config& config);

  const std::vector<double>& probs() const { return probs_; }

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  static EnvSpec MakeSpec(const Config& config);

  int64_t n_arms_;
  bool hide_task_;
  std::vector<double> probs_;
  double best_prob_ = 0.0;
};

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_BANDIT_H_
