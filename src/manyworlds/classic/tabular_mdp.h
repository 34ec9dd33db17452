// Random tabular MDP (MTEnv's UniformTMDP idea): each task is a reward table
// and a transition tensor over S states and A actions.
//
//   action:   Discrete(A).
//   env_obs:  Box(0, 1, (S + 1,)): one-hot of the current state, then the
//             last reward (0 after Reset). Every episode starts in state 0.
//   task_obs: Box(0, 1, (S*A + S*A*S,)): R flattened (index s*A + a), then P
//             flattened (index (s*A + a)*S + s'); zeros if hide_task.
//   reward:   Bernoulli(R[s, a]) from the env generator; then the next state
//             is drawn from P[s, a, :] (also the env generator).
//   end:      never terminates; truncated after `horizon` steps.
//   info:     expected_reward = R[s, a].
//   task state params: {"n_states": S, "n_actions": A,
//             "rewards": [S*A numbers in [0, 1]],
//             "transitions": [S*A*S numbers in [0, 1], each row summing to 1
//             within 1e-6]}. The task generator draws R[s, a] ~ U[0, 1]
//             (row-major), then for each (s, a) S draws N(0, 1) and takes
//             their softmax as P[s, a, :].
//   options:  n_states (int, 4, in [1, 100]), n_actions (int, 5, in
//             [1, 100]), horizon (int, 10, >= 1), hide_task (bool, false).
#ifndef MANYWORLDS_CLASSIC_TABULAR_MDP_H_
#define MANYWORLDS_CLASSIC_TABULAR_MDP_H_

#include <cstdint>
#include <vector>

#include "manyworlds/core/env.h"

namespace manyworlds::classic {

class TabularMdpEnv : public Env {
 public:
  static constexpr const char* kId = "tabular-mdp";

  struct Config {
    int64_t n_states = 4;
    int64_t n_actions = 5;
    int64_t horizon = 10;
    bool hide_task = false;
  };

  // Throws ConfigError on an out-of-range option.
  explicit TabularMdpEnv(const Config& config);

  int64_t n_states() const { return n_states_; }
  int64_t n_actions() const { return n_actions_; }
  double reward_mean(int64_t s, int64_t a) const { return rewards_[s * n_actions_ + a]; }
  double transition(int64_t s, int64_t a, int64_t next) const {
    return transitions_[(s * n_actions_ + a) * n_states_ + next];
  }
  int64_t state() const { return state_; }

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  static EnvSpec MakeSpec(const Config& config);
  TaskState MakeState(const std::vector<double>& rewards,
                      const std::vector<double>& transitions) const;

  int64_t n_states_;
  int64_t n_actions_;
  bool hide_task_;
  std::vector<double> rewards_;      // S*A
  std::vector<double> transitions_;  // S*A*S
  int64_t state_ = 0;
};

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_TABULAR_MDP_H_
