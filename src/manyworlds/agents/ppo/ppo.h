// Proximal policy optimisation (clipped surrogate; Schulman et al. 2017) on
// the shared policy-gradient base. Per iteration: `epochs` passes over the
// rollout in shuffled minibatches; each minibatch takes one Adam step of the
// policy on
//   -mean(min(r A, clip(r, 1 - clip_range, 1 + clip_range) A)) - c H
// (r = pi(a|s) / pi_old(a|s), c = entropy_coeff with entropy_method
// "regularized"), then, with the MLP baseline, one Adam step of the value
// network on mean((V(s) - R)^2) (garage optimises the two with separate
// optimizers too). max_grad_norm > 0 clips the policy gradient's norm.
// A learned task conditioning (task_encoder, moe) is stepped with the
// policy, by its own Adam at the same lr, on the same loss; with pcgrad the
// per-task gradients of both losses are combined by PCGrad first.
// MT-PPO is this with several tasks and architecture "mlp" (one-hot id).
#ifndef MANYWORLDS_AGENTS_PPO_PPO_H_
#define MANYWORLDS_AGENTS_PPO_PPO_H_

#include <cstdint>
#include <vector>

#include "manyworlds/agents/policy_gradient/policy_gradient.h"
#include "manyworlds/agents/ppo/ppo_config.h"

namespace manyworlds::agents {

// PPO's clipped surrogate on one minibatch, shared by PPO and TE-PPO.
struct ClippedSurrogate {
  torch::Tensor loss;       // -mean(min(r A, clip(r, 1 - eps, 1 + eps) A)), differentiable
  torch::Tensor per_sample;  // (B) the terms of that mean (negated), differentiable
  double approx_kl = 0.0;   // mean((r - 1) - log r), an estimate of KL(old || new)
  double clip_fraction = 0.0;  // share of rows with |r - 1| > eps
};
ClippedSurrogate ClippedSurrogateLoss(const torch::Tensor& log_probs,
                                      const torch::Tensor& old_log_probs,
                                      const torch::Tensor& advantages, double clip_range);

// Sums of the clipped-surrogate minibatches of one epoch (PPO, TE-PPO, RL2);
// the learners report their means, sum / count.
struct ClippedEpochSums {
  double policy_loss = 0, entropy = 0, approx_kl = 0, clip_fraction = 0;
  int64_t count = 0;
  // One minibatch: its loss and mean entropy (scalar tensors) and surrogate.
  void Add(const torch::Tensor& loss, const torch::Tensor& mean_entropy,
           const ClippedSurrogate& surrogate);
};

class PpoLearner : public PolicyGradientLearner {
 public:
  PpoLearner(const PpoConfig& config, const PolicySpaces& spaces);
  const PpoConfig& config() const { return ppo_; }

  // One pass of minibatch steps (policy and value) over the samples: the
  // unit `bench agent --algo ppo` times.
  Metrics Epoch(const PolicySamples& samples);

 protected:
  const char* algo_name() const override { return "ppo"; }
  Metrics OptimizePolicy(const PolicySamples& samples) override;
  void SaveExtra(torch::serialize::OutputArchive& archive) const override;
  void LoadExtra(torch::serialize::InputArchive& archive) override;

 private:
  PpoConfig ppo_;
  // One per policy module (policy_modules(): policy, then conditioning).
  std::vector<nn::FlatAdam> policy_optimizers_;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_PPO_PPO_H_
