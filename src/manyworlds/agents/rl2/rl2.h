// RL2 (Duan et al. 2016, "RL^2: Fast Reinforcement Learning via Slow
// Reinforcement Learning"), trained with PPO as garage's RL2PPO.
//
// Policy: a GRU over x_t = [obs_t, a_{t-1}, r_{t-1} * context_reward_scale,
// d_{t-1}] (a one-hot for Discrete actions; Box actions clipped to [-1, 1],
// as the env saw them; d = 1 where the previous step ended an episode; zeros
// at a trial's first step), then a linear head: Gaussian mean with a learned
// state-independent log std clamped to [min_std, max_std], or categorical
// logits. The task index is never an input: the policy must infer the task.
//
// Trials: one training iteration collects one trial (episodes_per_trial
// episodes of one task variation, the collector's trial mode) in every env.
// The hidden state carries over between the episodes of a trial and is reset
// between trials (ResetScope::kTrial or kTask; kEpisode keeps it).
//
// Update, as garage's RL2: the trial's episodes form one sequence, so values,
// returns and advantages span episodes (the trial's end is terminal); the
// baseline is garage's linear feature baseline over x_t and the step within
// the trial; PPO epochs over minibatches of whole trials, the GRU unrolled
// over the whole trial from a zero state (backpropagation through time).
//
// Differences from garage, and why:
// - garage's RL2Env gives [obs, 0, 0, 0] at an episode's reset, so the first
//   step of each later episode of a trial sees no reward; here it sees the
//   previous episode's last action and reward with d = 1. With one-step
//   episodes (the RL2 paper's bandits) garage's input would never carry a
//   reward at all.
// - d marks every episode end (terminated or truncated); garage marks
//   terminations only.
#ifndef MANYWORLDS_AGENTS_RL2_RL2_H_
#define MANYWORLDS_AGENTS_RL2_RL2_H_

#include <cstdint>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/policy_gradient/policy_gradient.h"
#include "manyworlds/agents/rl2/rl2_config.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/gru.h"
#include "manyworlds/nn/stochastic_policy.h"
#include "manyworlds/rl/linear_baseline.h"

namespace manyworlds::agents {

class Rl2Learner : public OnPolicyLearner, public Actor {
 public:
  // Throws ConfigError on a bad config or spaces.
  Rl2Learner(const Rl2Config& config, const PolicySpaces& spaces);

  Actor& AsActor() override { return *this; }
  ActorState Initial(int64_t num_envs) override;
  ActOutput Act(const torch::Tensor& obs, const torch::Tensor& task_index, ActorState& state,
                ActMode mode) override;
  // kTrial and kTask zero the rows' hidden state and context; kEpisode keeps them.
  void Reset(const torch::Tensor& envs, ResetScope scope, ActorState& state) override;
  bool WantsOutcomes() const override { return true; }
  void Observe(const StepOutcome& outcome, ActorState& state) override;

  Metrics Update(rl::RolloutBuffer& rollout) override;
  int64_t num_updates() const override { return num_updates_; }
  bool trials() const override { return true; }
  int64_t support_rounds() const override { return config_.episodes_per_trial - 1; }

  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive) override;

  // [a, r * scale, d] rows for actions (..., action_dim), rewards (...) and
  // episode ends (...): (..., context_dim).
  torch::Tensor Context(const torch::Tensor& actions, const torch::Tensor& rewards,
                        const torch::Tensor& ended) const;
  int64_t context_dim() const { return context_dim_; }
  const Rl2Config& config() const { return config_; }
  const std::vector<nn::FlatModule*>& modules() const { return modules_; }

 private:
  // The checkpoint's networks and optimizers in Save's order; Load reads the
  // same list (Self is const for Save).
  template <typename Archive, typename Self>
  static void TransferNetworks(Archive& archive, Self& self);
  // The policy over a (T, N, input) sequence from a zero state.
  nn::ActionDistribution Unroll(const torch::Tensor& x) const;

  Rl2Config config_;
  PolicySpaces spaces_;
  int64_t context_dim_ = 0;
  at::Generator generator_;
  nn::Gru gru_{nullptr};
  nn::StochasticPolicy head_{nullptr};
  std::vector<nn::FlatModule*> modules_;
  std::vector<nn::FlatAdam> optimizers_;
  rl::LinearFeatureBaseline baseline_;
  int64_t num_updates_ = 0;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_RL2_RL2_H_
