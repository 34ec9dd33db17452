// Soft actor-critic for one or many tasks (MTRL's MT-SAC structure).
//
//   SacLearner sac(config, obs_dim, action_dim, num_tasks);
//   Metrics m = sac.Update(batch);             // one gradient step
//   torch::Tensor a = sac.Act(obs, /*deterministic=*/false);
//
// One update, in MTRL's order:
//  1. critic target y = r + discount (1 - done) (min_j Q'_j(s', a') - alpha log pi(a'|s'))
//     with a' ~ pi(.|s') and the target critics, no gradient;
//  2. critic loss MSE(Q1, y) + MSE(Q2, y), one backward, fused Adam step;
//  3. every actor_update_freq updates: actor loss mean(alpha log pi(a|s) -
//     min_j Q_j(s, a)) with the updated critics run on detached weights (the
//     backward reaches the action but computes no critic weight gradients),
//     and temperature loss mean(alpha (-log pi - target_entropy)) whose
//     gradient in log-alpha is computed in closed form;
//  4. every critic_target_update_freq updates: Polyak update of the targets.
// Temperatures are per task with disentangled_alpha, indexed by task_index.
//
// Metrics: critic_loss, q_mean, and on actor steps actor_loss, alpha (mean
// temperature used), alpha_loss, entropy (-mean log pi).
//
// The learner calls nn::ConfigureTorchThreads() (intra-op threads = 1, GEMM
// threads from OpenBLAS); see nn/threads.h. Not thread-safe.
#ifndef MANYWORLDS_AGENTS_SAC_H_
#define MANYWORLDS_AGENTS_SAC_H_

#include <cstdint>

#include <torch/torch.h>

#include "manyworlds/agents/batch.h"
#include "manyworlds/agents/metrics.h"
#include "manyworlds/agents/sac_config.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/gaussian_policy.h"
#include "manyworlds/nn/twin_critic.h"

namespace manyworlds::agents {

// r + discount * (1 - done) * (next_q - alpha * next_log_prob), elementwise
// over (B); alpha broadcasts ((B) or (1)).
torch::Tensor SoftTdTarget(const torch::Tensor& reward, const torch::Tensor& done,
                           const torch::Tensor& next_q, const torch::Tensor& next_log_prob,
                           const torch::Tensor& alpha, double discount);

class SacLearner {
 public:
  // Validates the config (ConfigError) and the dims (> 0).
  SacLearner(const SacConfig& config, int64_t obs_dim, int64_t action_dim,
             int64_t num_tasks = 1);
  // A copy would share the networks (module holders are shared pointers).
  SacLearner(const SacLearner&) = delete;
  SacLearner& operator=(const SacLearner&) = delete;
  SacLearner(SacLearner&&) = default;
  SacLearner& operator=(SacLearner&&) = default;

  // One update on a batch (any size). Throws Error on a malformed batch, or
  // if the critic loss exceeds config.max_critic_loss (before any step).
  Metrics Update(const Batch& batch);

  // Actions in (-1, 1) for obs (B, obs_dim) or (obs_dim): sampled, or
  // tanh(mean) when deterministic. Runs under InferenceMode; the result is
  // an inference tensor (copy it out, do not feed it to autograd).
  torch::Tensor Act(const torch::Tensor& obs, bool deterministic);

  // The critic target y (B) of step 1, drawing a' from this learner's
  // generator. Exposed for tests and diagnostics.
  torch::Tensor CriticTarget(const Batch& batch);

  // Temperatures exp(log_alpha): (num_tasks) if disentangled, else (1).
  torch::Tensor Alpha() const { return log_alpha_.exp(); }
  double target_entropy() const { return target_entropy_; }
  int64_t num_updates() const { return num_updates_; }
  const SacConfig& config() const { return config_; }
  int64_t obs_dim() const { return obs_dim_; }
  int64_t action_dim() const { return action_dim_; }
  int64_t num_tasks() const { return num_tasks_; }

  nn::GaussianPolicy& actor() { return actor_; }
  nn::TwinCritic& critic() { return critic_; }
  // Drives initialisation and every sampled action.
  at::Generator& generator() { return generator_; }

  // Full training state: networks, targets, temperatures, optimizers,
  // update count, generator. Load throws Error on a size mismatch.
  void Save(torch::serialize::OutputArchive& archive) const;
  void Load(torch::serialize::InputArchive& archive);

 private:
  // Per-sample temperatures (B), or (1) when shared.
  torch::Tensor SampleAlpha(const torch::Tensor& task_index) const;
  torch::Tensor CriticTargetWithAlpha(const Batch& batch, const torch::Tensor& alpha);

  SacConfig config_;
  int64_t obs_dim_;
  int64_t action_dim_;
  int64_t num_tasks_;
  double target_entropy_;
  at::Generator generator_;
  nn::GaussianPolicy actor_{nullptr};
  nn::TwinCritic critic_{nullptr};
  torch::Tensor log_alpha_;  // (num_tasks) or (1)
  nn::FlatAdam actor_optimizer_;
  nn::FlatAdam critic_optimizer_;
  nn::FlatAdam alpha_optimizer_;
  int64_t num_updates_ = 0;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_SAC_H_
