// MAML-TRPO and MAML-PPO (Finn et al. 2017, "Model-Agnostic Meta-Learning";
// garage's MAMLTRPO and MAMLPPO): a policy whose parameters adapt to a task with one vanilla
// policy-gradient step, meta-trained by TRPO on the post-adaptation returns
// with gradients through the inner step.
//
// Collection: an iteration is a trial of 2K episodes per env (K =
// episodes_per_task), every env on its own task variation: K episodes with
// the meta-parameters theta, Adapt, K episodes with the env's adapted
// parameters theta'_i. Each env is one task instance of the meta-batch.
//
// Inner step (Adapt and the update share one: Adapt in the training loop
// keeps its graph for the update, see Adaptation): for env i, advantages A of its
// pre-adaptation episodes (GAE over each episode, every episode end
// terminal, the linear feature baseline fitted to those episodes;
// centred), L_i(theta) = -mean(log pi_theta(a|s) A), theta'_i = theta -
// inner_lr * grad L_i(theta).
//
// Outer step: maximise mean_i mean_t [pi_theta'_i(theta)(a|s) /
// pi_old(a|s)] A_post over the post-adaptation episodes subject to
// mean_i KL(pi_old_i || pi_theta'_i(theta)) <= max_kl: conjugate gradient on
// Fisher-vector products taken through the inner step (second and third
// derivatives of the inner loss), then a backtracking line search that
// re-adapts at every candidate.
//
// MAML-PPO (outer: ppo): outer_epochs Adam steps on
// -mean_i mean_t min(r A, clip(r, 1 - clip_range, 1 + clip_range) A), r the
// same ratio, each re-adapting from theta with create_graph.
//
// Meta-test: the exploration episodes are the pre-adaptation episodes;
// Adapt takes the inner step per env from what Observe recorded.
#ifndef MANYWORLDS_AGENTS_MAML_MAML_H_
#define MANYWORLDS_AGENTS_MAML_MAML_H_

#include <cstdint>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/maml/maml_config.h"
#include "manyworlds/agents/policy_gradient/policy_gradient.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/mlp.h"
#include "manyworlds/nn/stochastic_policy.h"

namespace manyworlds::agents {

// One task instance's episodes, flattened in time order.
struct MamlEpisodes {
  torch::Tensor obs;         // (B, obs_dim)
  torch::Tensor actions;     // (B, action_dim)
  torch::Tensor log_probs;   // (B) at collection (post-adaptation data)
  torch::Tensor advantages;  // (B)
  torch::Tensor returns;     // (B) undiscounted episode-return contribution (reward)
};

class MamlLearner : public OnPolicyLearner, public Actor {
 public:
  // Throws ConfigError on a bad config or spaces.
  MamlLearner(const MamlConfig& config, const PolicySpaces& spaces);

  Actor& AsActor() override { return *this; }
  ActOutput Act(const torch::Tensor& obs, const torch::Tensor& task_index, ActorState& state,
                ActMode mode) override;
  // kEpisode keeps what was observed; kTrial and kTask forget it and the
  // adaptation of the rows.
  void Reset(const torch::Tensor& envs, ResetScope scope, ActorState& state) override;
  bool WantsOutcomes() const override { return true; }
  void Observe(const StepOutcome& outcome, ActorState& state) override;
  void Adapt(const torch::Tensor& envs, ActorState& state) override;

  Metrics Update(rl::RolloutBuffer& rollout) override;
  int64_t num_updates() const override { return num_updates_; }
  bool trials() const override { return true; }
  int64_t adapt_after_rounds() const override { return config_.episodes_per_task; }

  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive) override;

  nn::StochasticPolicy& policy() { return policy_; }
  const MamlConfig& config() const { return config_; }

  // Advantages of episodes given as (T) rows of one env: rewards, episode
  // ends (the last row must end one), valid rows (weights 0/1).
  // The baseline is fitted on these episodes alone (see MamlConfig).
  torch::Tensor Advantages(const torch::Tensor& obs, const torch::Tensor& rewards,
                           const torch::Tensor& ended, const torch::Tensor& valid);
  // theta - inner_lr * grad L(theta) on the episodes (rows with weight 0
  // ignored); create_graph keeps the inner gradient differentiable.
  std::vector<torch::Tensor> InnerStep(at::ArrayRef<torch::Tensor> params,
                                       const MamlEpisodes& episodes, const torch::Tensor& weights,
                                       bool create_graph) const;

 private:
  MamlConfig config_;
  PolicySpaces spaces_;
  at::Generator generator_;
  nn::StochasticPolicy policy_{nullptr};
  nn::FlatAdam outer_optimizer_;  // MAML-PPO
  // baseline value_network: the network refitted per task, and the initial
  // weights every fit starts from (drawn from the seed, never trained).
  nn::Mlp value_net_{nullptr};
  torch::Tensor value_init_;

  // Baseline values of every row, fitted on rows `fit_rows` (step = index
  // within the episode, returns = discounted returns).
  torch::Tensor BaselineValues(const torch::Tensor& obs, const torch::Tensor& steps,
                               const torch::Tensor& returns, const torch::Tensor& fit_rows);
  int64_t num_updates_ = 0;

  // What the training loop's Adapt computed (ActorState::learning), for the
  // next Update: each env's pre-adaptation episodes with their advantages,
  // and its adapted parameters with the inner step's graph. The update
  // reuses them where its rollout holds the same episodes at the same theta,
  // so the inner step at theta runs once per iteration.
  struct Adaptation {
    int64_t num_updates = -1;  // theta's version when Adapt ran
    std::vector<MamlEpisodes> pre;
    std::vector<torch::Tensor> ended;  // each env's episode ends, as the advantages saw them
    std::vector<std::vector<torch::Tensor>> adapted;
  };
  Adaptation adaptation_;
  // True if Adapt's record of env i is of these pre-adaptation episodes
  // (rows of every env valid) at the current theta.
  bool Adapted(int64_t i, const MamlEpisodes& pre, const torch::Tensor& ended) const;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_MAML_MAML_H_
