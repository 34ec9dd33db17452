#include "manyworlds/agents/ppo/ppo.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/pcgrad.h"

namespace manyworlds::agents {
namespace {

// The policy's optimizer keeps its key of the one-module layout.
std::string PolicyOptimizerKey(size_t i) {
  return i == 0 ? "policy_optimizer" : "conditioning_optimizer_" + std::to_string(i);
}

}  // namespace

void PpoConfig::Validate() const {
  PolicyGradientConfig::Validate();
  RequireField(FinitePositive(lr), "lr", "finite and > 0", lr);
  RequireField(epochs >= 1 && epochs <= 10000, "epochs", "in [1, 10000]", epochs);
  RequireField(minibatch_size >= 1 && minibatch_size <= 100000000, "minibatch_size", "in [1, 1e8]",
               minibatch_size);
  RequireField(clip_range > 0 && clip_range < 1, "clip_range", "in (0, 1)", clip_range);
  RequireField(std::isfinite(max_grad_norm) && max_grad_norm >= 0, "max_grad_norm",
               "finite and >= 0", max_grad_norm);
}

ClippedSurrogate ClippedSurrogateLoss(const torch::Tensor& log_probs,
                                      const torch::Tensor& old_log_probs,
                                      const torch::Tensor& advantages, double clip_range) {
  const torch::Tensor log_ratio = log_probs - old_log_probs;
  const torch::Tensor ratio = log_ratio.exp();
  const torch::Tensor surrogate = torch::minimum(
      ratio * advantages, ratio.clamp(1.0 - clip_range, 1.0 + clip_range) * advantages);
  ClippedSurrogate out;
  out.per_sample = -surrogate;
  out.loss = -surrogate.mean();
  torch::NoGradGuard no_grad;
  // (r - 1) - log r: an unbiased, non-negative estimate of KL(old || new)
  out.approx_kl = ((ratio - 1.0) - log_ratio).mean().item<double>();
  out.clip_fraction = ((ratio - 1.0).abs() > clip_range).to(torch::kFloat32).mean().item<double>();
  return out;
}

void ClippedEpochSums::Add(const torch::Tensor& loss, const torch::Tensor& mean_entropy,
                           const ClippedSurrogate& surrogate) {
  policy_loss += loss.item<double>();
  entropy += mean_entropy.item<double>();
  approx_kl += surrogate.approx_kl;
  clip_fraction += surrogate.clip_fraction;
  ++count;
}

PpoLearner::PpoLearner(const PpoConfig& config, const PolicySpaces& spaces)
    : PolicyGradientLearner(Validated(config), spaces), ppo_(config) {
  for (const nn::FlatModule* m : policy_modules()) {
    policy_optimizers_.emplace_back(m->num_params(), nn::AdamOptions{.lr = config.lr});
  }
}

Metrics PpoLearner::Epoch(const PolicySamples& s) {
  const int64_t b = s.size();
  const int64_t mb = std::min(ppo_.minibatch_size, b);
  const double regularizer = ppo_.entropy_method == "regularized" ? ppo_.entropy_coeff : 0.0;
  const torch::Tensor perm = torch::randperm(b, generator_, torch::kInt64);
  ClippedEpochSums sums;
  double value_loss = 0, pcgrad_conflicts = 0;
  for (int64_t lo = 0; lo < b; lo += mb) {
    const torch::Tensor rows = perm.narrow(0, lo, std::min(mb, b - lo));
    const nn::ActionDistribution d = PolicyOn(s, rows);
    const ClippedSurrogate surrogate = ClippedSurrogateLoss(
        d.LogProb(s.actions.index_select(0, rows)), s.log_probs.index_select(0, rows),
        s.advantages.index_select(0, rows), ppo_.clip_range);
    const torch::Tensor per_sample_entropy = d.Entropy();
    const torch::Tensor ent = per_sample_entropy.mean();
    const torch::Tensor loss = surrogate.loss - regularizer * ent;
    const std::vector<nn::FlatModule*>& modules = policy_modules();
    for (nn::FlatModule* m : modules) m->ZeroGrad();
    if (ppo_.pcgrad) {
      const torch::Tensor per_sample = regularizer > 0
                                           ? surrogate.per_sample - regularizer * per_sample_entropy
                                           : surrogate.per_sample;
      pcgrad_conflicts += nn::PcGradBackward(per_sample, s.tasks.index_select(0, rows),
                                             spaces_.num_tasks, modules, generator_)
                              .conflict_fraction();
    } else {
      loss.backward();
    }
    ClipGradNorm(modules, ppo_.max_grad_norm);
    for (size_t i = 0; i < modules.size(); ++i) {
      policy_optimizers_[i].Step(modules[i]->flat(), modules[i]->flat_grad());
    }
    sums.Add(loss, ent, surrogate);
    if (uses_value_network()) value_loss += ValueStep(s, rows);
  }
  const auto count = static_cast<double>(sums.count);
  Metrics m;
  m.Set("policy_loss", sums.policy_loss / count);
  if (uses_value_network()) m.Set("value_loss", value_loss / count);
  m.Set("entropy", sums.entropy / count);
  m.Set("approx_kl", sums.approx_kl / count);
  m.Set("clip_fraction", sums.clip_fraction / count);
  if (ppo_.pcgrad) m.Set("pcgrad_conflicts", pcgrad_conflicts / count);
  return m;
}

Metrics PpoLearner::OptimizePolicy(const PolicySamples& s) {
  Metrics last;
  for (int64_t e = 0; e < ppo_.epochs; ++e) last = Epoch(s);
  return last;  // the last epoch's means (approx_kl then says how far the policy moved)
}

void PpoLearner::SaveExtra(torch::serialize::OutputArchive& archive) const {
  for (size_t i = 0; i < policy_optimizers_.size(); ++i) {
    WriteOptimizer(archive, PolicyOptimizerKey(i).c_str(), policy_optimizers_[i]);
  }
}

void PpoLearner::LoadExtra(torch::serialize::InputArchive& archive) {
  for (size_t i = 0; i < policy_optimizers_.size(); ++i) {
    ReadOptimizer(archive, PolicyOptimizerKey(i).c_str(), policy_optimizers_[i]);
  }
}

}  // namespace manyworlds::agents
