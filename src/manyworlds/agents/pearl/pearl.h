// PEARL (Rakelly et al. 2019): soft actor-critic conditioned on a latent
// task variable z inferred from context by a permutation-invariant encoder.
//
// Networks (oyster's sizes, pearl_config.h): the context encoder maps each
// transition c = [obs, action, reward] to a Gaussian factor (mu, softplus
// sigma^2); the posterior q(z | c_1..n) is their product,
//   sigma^2 = 1 / sum_i 1/sigma_i^2,  mu = sigma^2 sum_i mu_i / sigma_i^2
// (sigma_i^2 clamped at >= 1e-7; no context: the prior N(0, I)). Without the
// information bottleneck z is the mean of the mu_i. Twin Q(s, a, z), V(s, z)
// with a Polyak target V, and a tanh-Gaussian policy pi(a | s, z).
//
// One Update on T tasks, each with a context batch and an RL batch (rows
// grouped by task), in oyster's order (rlkit/torch/sac/sac.py):
//  1. posterior per task, z ~ q by reparameterisation; KL(q || N(0, I))
//     summed over tasks;
//  2. Q loss MSE(Q_j(s, a, z), r * reward_scale + discount (1 - done)
//     V'(s', z)) summed over the two critics; kl_lambda KL + Q loss is
//     backpropagated into the critics and the encoder, which both step;
//  3. a' ~ pi(s, z.detach()) reparameterised; V loss MSE(V(s, z.detach()),
//     min_j Q_j(s, a', z) - log pi(a')) with the stepped critics; V steps,
//     then the target V moves by tau;
//  4. policy loss mean(log pi(a') - min_j Q_j(s, a', z)) + policy_mean_reg
//     mean(mu^2) + policy_std_reg mean(log_std^2); the policy steps.
// The entropy weight is fixed at 1 (reward_scale sets the trade-off), as in
// the paper.
//
// As an Actor (meta-test, evaluation, rollouts) it keeps per env its belief
// (ActorState::context, (N, 2Z) = [mean, variance]), its current z
// (ActorState::latent; NaN rows are drawn from the belief at the next Act)
// and the transitions it observed (ActorState::history, one (N, D + 1) row
// per step, the last column 1 where the row counts). z is redrawn from the
// belief at every episode start; Adapt sets the belief to the posterior of
// the env's observed transitions (PEARL's adapt_policy). Until then the
// belief is the prior. Draws use the state's generator; Initial gives every
// state one seeded from config.seed, so evaluations never move the
// learner's training stream. kDeterministic acts with tanh(mean) for the
// drawn z.
//
// Differences from oyster, and why: orthogonal initialisation (the
// library's, as SAC) instead of rlkit's fan-in init; the policy's log-std is
// bounded by a smooth tanh map to [log_std_min, log_std_max] (SAC's) instead
// of a clamp.
#ifndef MANYWORLDS_AGENTS_PEARL_PEARL_H_
#define MANYWORLDS_AGENTS_PEARL_PEARL_H_

#include <torch/torch.h>

#include <cstdint>
#include <vector>

#include "manyworlds/agents/actor.h"
#include "manyworlds/agents/batch.h"
#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/metrics.h"
#include "manyworlds/agents/pearl/pearl_config.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/gaussian_policy.h"
#include "manyworlds/nn/mlp.h"

namespace manyworlds::agents {

// A Gaussian belief over z per task or env: mean and variance (M, Z).
struct LatentBelief {
  torch::Tensor mean;
  torch::Tensor var;
};

class PearlLearner : public Learner, public Actor {
 public:
  // Throws ConfigError on a bad config or dims.
  PearlLearner(const PearlConfig& config, int64_t obs_dim, int64_t action_dim);
  PearlLearner(const PearlLearner&) = delete;
  PearlLearner& operator=(const PearlLearner&) = delete;

  // Width of a context row [obs, action, reward].
  int64_t context_dim() const { return obs_dim_ + action_dim_ + 1; }
  // Context rows of a batch: (B, context_dim).
  static torch::Tensor ContextRows(const Batch& batch);

  // The posterior of each of M groups from its context rows (M, C,
  // context_dim), weighted by `weight` (M, C) (1 = the row counts; undefined
  // = all count). Groups with no counting row get the prior. Differentiable
  // in the encoder when grad mode is on.
  LatentBelief Posterior(const torch::Tensor& context, const torch::Tensor& weight = {}) const;
  // z ~ N(mean, var) per row (inference mode).
  static torch::Tensor SampleLatent(const LatentBelief& belief, at::Generator& generator);
  LatentBelief Prior(int64_t rows) const;

  // Actions in (-1, 1) for obs (N, obs_dim) and latents (N, latent_dim):
  // sampled from the policy, or tanh(mean). Inference mode.
  torch::Tensor ActWithLatent(const torch::Tensor& obs, const torch::Tensor& latent,
                              bool deterministic, at::Generator& generator);

  // One gradient step on `num_tasks` tasks: `context` holds embedding rows
  // per task and `rl` RL rows per task, each grouped by task in the same
  // task order. Throws Error on malformed batches or non-finite losses
  // (before any parameter changes).
  Metrics Update(const Batch& context, const Batch& rl, int64_t num_tasks);

  Actor& AsActor() override { return *this; }
  ActorState Initial(int64_t num_envs) override;
  ActOutput Act(const torch::Tensor& obs, const torch::Tensor& task_index, ActorState& state,
                ActMode mode) override;
  // kTrial and kTask: the rows' belief returns to the prior, their history
  // stops counting and z is redrawn; kEpisode: z is redrawn.
  void Reset(const torch::Tensor& envs, ResetScope scope, ActorState& state) override;
  bool WantsOutcomes() const override { return true; }
  void Observe(const StepOutcome& outcome, ActorState& state) override;
  void Adapt(const torch::Tensor& envs, ActorState& state) override;

  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive) override;

  int64_t num_updates() const { return num_updates_; }
  const PearlConfig& config() const { return config_; }
  int64_t obs_dim() const { return obs_dim_; }
  int64_t action_dim() const { return action_dim_; }
  at::Generator& generator() { return generator_; }

 private:
  // The checkpoint's networks and optimizers in Save's order; Load reads the
  // same list (Self is const for Save).
  template <typename Archive, typename Self>
  static void TransferNetworks(Archive& archive, Self& self);

  PearlConfig config_;
  int64_t obs_dim_;
  int64_t action_dim_;
  at::Generator generator_;
  nn::Mlp encoder_{nullptr};
  nn::GaussianPolicy policy_{nullptr};
  nn::EnsembleMlp critic_{nullptr};  // twin Q over [obs, action, z]
  nn::Mlp value_{nullptr};           // V over [obs, z]
  nn::Mlp value_target_{nullptr};
  nn::FlatAdam encoder_optimizer_;
  nn::FlatAdam policy_optimizer_;
  nn::FlatAdam critic_optimizer_;
  nn::FlatAdam value_optimizer_;
  int64_t num_updates_ = 0;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_PEARL_PEARL_H_
