// The shared half of PPO and TRPO: networks, task conditioning, the batched
// actor, values and baselines, GAE, advantage centring, checkpoints. A
// subclass supplies only the policy optimisation (OptimizePolicy) and, if it
// wants, its own value-function fit.
//
// Update(rollout), in garage's order:
//  1. values V(x_t) and bootstrap values V(final x) with the current value
//     function or linear baseline (x = the task-conditioned observation);
//  2. with entropy_method "max", rewards r_t + entropy_coeff * (-log pi(a_t|s_t));
//  3. GAE(gamma, lambda) with Gymnasium's episode flags (rl::ComputeGae);
//  4. the linear baseline is refitted to the discounted returns (after the
//     advantages used its previous fit, as garage does);
//  5. advantages centred (mean 0, std 1) if center_advantages;
//  6. OptimizePolicy (PPO: clipped epochs, which also train the value
//     network; TRPO: natural-gradient step, then FitValue).
#ifndef MANYWORLDS_AGENTS_POLICY_GRADIENT_POLICY_GRADIENT_H_
#define MANYWORLDS_AGENTS_POLICY_GRADIENT_POLICY_GRADIENT_H_

#include <cstdint>
#include <memory>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/policy_gradient/policy_gradient_config.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/stochastic_policy.h"
#include "manyworlds/nn/task_conditioning.h"
#include "manyworlds/rl/linear_baseline.h"

namespace manyworlds::agents {

// What a learner needs to know of the envs.
struct PolicySpaces {
  int64_t obs_dim = 0;
  int64_t action_dim = 0;   // Box size; 1 for Discrete
  int64_t num_actions = 0;  // > 0 for a Discrete action space
  int64_t num_tasks = 1;
};

// The Gaussian or categorical policy of an on-policy learner over inputs of
// input_dim: the action space of `spaces`, the network's size and std bounds
// from the config (hidden_dim, num_layers, init_std, min_std, max_std).
template <typename Config>
nn::StochasticPolicyOptions PolicyNetworkOptions(const Config& config, const PolicySpaces& spaces,
                                                 int64_t input_dim) {
  return {.input_dim = input_dim,
          .action_dim = spaces.action_dim,
          .num_actions = spaces.num_actions,
          .hidden_dim = config.hidden_dim,
          .num_layers = config.num_layers,
          .init_std = config.init_std,
          .min_std = config.min_std,
          .max_std = config.max_std};
}

// One iteration's samples, flattened to B = T * N rows.
struct PolicySamples {
  torch::Tensor x;           // (B, input_dim) task-conditioned observations (no history)
  torch::Tensor obs;         // (B, obs_dim) raw observations (learned conditionings)
  torch::Tensor tasks;       // (B) int64 task index
  torch::Tensor head;        // (B) task index for multi-head nets, else undefined
  torch::Tensor actions;     // (B, action_dim)
  torch::Tensor log_probs;   // (B) at collection
  torch::Tensor advantages;  // (B), centred if configured
  torch::Tensor returns;     // (B) lambda-returns (value targets)
  torch::Tensor episode_steps;  // (B)
  int64_t size() const { return x.size(0); }
};

class PolicyGradientLearner : public OnPolicyLearner, public Actor {
 public:
  PolicyGradientLearner(const PolicyGradientConfig& config, const PolicySpaces& spaces);

  Actor& AsActor() override { return *this; }
  ActOutput Act(const torch::Tensor& obs, const torch::Tensor& task_index, ActorState& state,
                ActMode mode) override;
  Metrics Update(rl::RolloutBuffer& rollout) final;

  // The network input x(obs, task) of the task conditioning
  // (nn/task_conditioning.h), without autograd history.
  torch::Tensor NetworkInput(const torch::Tensor& obs, const torch::Tensor& task_index) const;
  // The policy on rows of the samples (all rows if `rows` is undefined),
  // differentiable in the policy and the learned task conditioning.
  nn::ActionDistribution PolicyOn(const PolicySamples& samples,
                                  const torch::Tensor& rows = {}) const;
  // Value estimates (B) of task-conditioned inputs at episode steps t (B).
  torch::Tensor Values(const torch::Tensor& x, const torch::Tensor& head,
                       const torch::Tensor& t) const;

  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive) override;

  nn::StochasticPolicy& policy() { return policy_; }
  // The policy and the learned parts of its task conditioning: what the
  // policy objective trains (TRPO's flat parameter vector, in this order).
  const std::vector<nn::FlatModule*>& policy_modules() const { return policy_modules_; }
  const PolicySpaces& spaces() const { return spaces_; }
  int64_t num_updates() const override { return num_updates_; }
  at::Generator& generator() { return generator_; }

 protected:
  virtual const char* algo_name() const = 0;
  virtual Metrics OptimizePolicy(const PolicySamples& samples) = 0;
  // Extra state of a subclass (optimizers).
  virtual void SaveExtra(torch::serialize::OutputArchive&) const {}
  virtual void LoadExtra(torch::serialize::InputArchive&) {}

  // One Adam step of the value network on a minibatch; returns the loss.
  double ValueStep(const PolicySamples& samples, const torch::Tensor& rows);
  // vf_epochs passes of minibatch value regression (TRPO's value fit).
  double FitValue(const PolicySamples& samples, int64_t epochs, int64_t minibatch_size);
  bool uses_value_network() const { return static_cast<bool>(value_); }
  torch::Tensor Heads(const torch::Tensor& task_index) const;
  // The checkpoint's networks in Save's order; Load reads the same list
  // (Self is const for Save).
  template <typename Archive, typename Self>
  static void TransferNetworks(Archive& archive, Self& self);

  PolicyGradientConfig config_;
  PolicySpaces spaces_;
  int64_t input_dim_ = 0;
  at::Generator generator_;
  std::unique_ptr<nn::TaskConditioning> conditioning_;
  nn::StochasticPolicy policy_{nullptr};
  std::vector<nn::FlatModule*> policy_modules_;
  nn::ValueNetwork value_{nullptr};
  std::unique_ptr<rl::LinearFeatureBaseline> linear_;
  nn::FlatAdam value_optimizer_;
  int64_t num_updates_ = 0;
};

// Explained variance 1 - Var(y - y_hat) / Var(y) (a value-fit diagnostic).
double ExplainedVariance(const torch::Tensor& prediction, const torch::Tensor& target);

// Throws Error naming `what` and the algorithm if t holds a NaN or infinity
// (a diverged baseline or policy stops the run with a reason instead of
// sending NaN actions to the envs).
void RequireFinite(const torch::Tensor& t, const char* algo, const char* what);

// Scales grad to at most max_norm (no-op for max_norm <= 0); returns the norm.
double ClipGradNorm(const torch::Tensor& grad, double max_norm);
// The same over the modules' flat gradients taken together.
double ClipGradNorm(const std::vector<nn::FlatModule*>& modules, double max_norm);

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_POLICY_GRADIENT_POLICY_GRADIENT_H_
