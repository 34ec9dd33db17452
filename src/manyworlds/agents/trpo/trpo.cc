#include "manyworlds/agents/trpo/trpo.h"

#include <cmath>
#include <vector>

#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/pcgrad.h"

namespace manyworlds::agents {
void TrpoConfig::Validate() const {
  PolicyGradientConfig::Validate();
  RequireField(FinitePositive(max_kl), "max_kl", "finite and > 0", max_kl);
  RequireField(cg_iters >= 1 && cg_iters <= 1000, "cg_iters", "in [1, 1000]", cg_iters);
  RequireField(std::isfinite(cg_damping) && cg_damping >= 0, "cg_damping", ">= 0", cg_damping);
  RequireField(backtrack_ratio > 0 && backtrack_ratio < 1, "backtrack_ratio", "in (0, 1)",
               backtrack_ratio);
  RequireField(max_backtracks >= 1 && max_backtracks <= 1000, "max_backtracks", "in [1, 1000]",
               max_backtracks);
  RequireField(vf_epochs >= 0 && vf_epochs <= 10000, "vf_epochs", "in [0, 10000]", vf_epochs);
  RequireField(vf_minibatch_size >= 1 && vf_minibatch_size <= 100000000, "vf_minibatch_size",
               "in [1, 1e8]", vf_minibatch_size);
}

torch::Tensor FlatGradient(const std::vector<torch::Tensor>& grads,
                           at::ArrayRef<torch::Tensor> params) {
  std::vector<torch::Tensor> flat;
  flat.reserve(grads.size());
  for (size_t i = 0; i < grads.size(); ++i) {
    flat.push_back(grads[i].defined() ? grads[i].reshape({-1})
                                      : torch::zeros({params[i].numel()}, params[i].options()));
  }
  return torch::cat(flat);
}

void TrustRegionResult::WriteTo(Metrics& m) const {
  m.Set("step_accepted", accepted ? 1.0 : 0.0);
  m.Set("backtracks", static_cast<double>(backtracks));
  m.Set("kl", kl);
  if (accepted) m.Set("surrogate_after", surrogate_after);
}

TrustRegionResult TrustRegionStep(const torch::Tensor& gradient,
                                  const std::function<torch::Tensor(const torch::Tensor&)>& fisher,
                                  const torch::Tensor& before,
                                  const std::function<void(const torch::Tensor&)>& set_params,
                                  const std::function<std::pair<double, double>()>& evaluate,
                                  double surrogate_before, const TrustRegionOptions& o) {
  TrustRegionResult result;
  result.backtracks = o.max_backtracks;
  const torch::Tensor direction = ConjugateGradient(fisher, gradient.detach(), o.cg_iters);
  const double shs = direction.dot(fisher(direction)).item<double>();
  if (!(shs > 0 && std::isfinite(shs))) return result;
  const torch::Tensor full_step = direction * std::sqrt(2.0 * o.max_kl / shs);
  double fraction = 1.0;
  for (int64_t k = 0; k < o.max_backtracks; ++k, fraction *= o.backtrack_ratio) {
    set_params(before + fraction * full_step);
    const auto [value, kl] = evaluate();
    if (std::isfinite(kl) && kl <= o.max_kl && value > surrogate_before) {
      result.accepted = true;
      result.kl = kl;
      result.surrogate_after = value;
      result.backtracks = k;
      return result;
    }
  }
  set_params(before);
  return result;
}

torch::Tensor ConjugateGradient(const std::function<torch::Tensor(const torch::Tensor&)>& product,
                                const torch::Tensor& b, int64_t iterations) {
  torch::Tensor x = torch::zeros_like(b);
  torch::Tensor r = b.clone();
  torch::Tensor p = b.clone();
  double rr = r.dot(r).item<double>();
  for (int64_t i = 0; i < iterations && rr > 1e-10; ++i) {
    const torch::Tensor ap = product(p);
    const double alpha = rr / (p.dot(ap).item<double>() + 1e-12);
    x.add_(p, alpha);
    r.add_(ap, -alpha);
    const double next = r.dot(r).item<double>();
    p = r + (next / rr) * p;
    rr = next;
  }
  return x;
}

TrpoLearner::TrpoLearner(const TrpoConfig& config, const PolicySpaces& spaces)
    : PolicyGradientLearner(Validated(config), spaces), trpo_(config) {}

Metrics TrpoLearner::OptimizePolicy(const PolicySamples& s) {
  // The parameters the step moves: the policy's, then the learned task
  // conditioning's, as one vector.
  const std::vector<nn::FlatModule*>& modules = policy_modules();
  std::vector<torch::Tensor> params;
  for (const nn::FlatModule* m : modules) {
    params.insert(params.end(), m->params().begin(), m->params().end());
  }
  auto flat_values = [&] {
    std::vector<torch::Tensor> parts;
    for (const nn::FlatModule* m : modules) parts.push_back(m->flat());
    return torch::cat(parts);
  };
  auto set_flat_values = [&](const torch::Tensor& values) {
    torch::NoGradGuard no_grad;
    int64_t offset = 0;
    for (const nn::FlatModule* m : modules) {
      m->flat().copy_(values.narrow(0, offset, m->num_params()));
      offset += m->num_params();
    }
  };
  const double regularizer = trpo_.entropy_method == "regularized" ? trpo_.entropy_coeff : 0.0;
  const nn::ActionDistribution old = PolicyOn(s).Detached();

  auto per_sample_surrogate = [&](const nn::ActionDistribution& d) {
    const torch::Tensor ratio = (d.LogProb(s.actions) - s.log_probs).exp();
    torch::Tensor value = ratio * s.advantages;
    if (regularizer > 0) value = value + regularizer * d.Entropy();
    return value;
  };
  auto surrogate = [&](const nn::ActionDistribution& d) { return per_sample_surrogate(d).mean(); };

  Metrics m;
  const torch::Tensor per_sample = per_sample_surrogate(PolicyOn(s));
  const torch::Tensor surr = per_sample.mean();
  torch::Tensor g;
  if (trpo_.pcgrad) {
    // PCGrad on the per-task losses -surrogate; g is the ascent direction.
    for (nn::FlatModule* module : modules) module->ZeroGrad();
    m.Set("pcgrad_conflicts",
          nn::PcGradBackward(-per_sample, s.tasks, spaces_.num_tasks, modules, generator_)
              .conflict_fraction());
    std::vector<torch::Tensor> grads;
    for (const nn::FlatModule* module : modules) grads.push_back(module->flat_grad());
    g = -torch::cat(grads);
  } else {
    g = FlatGradient(torch::autograd::grad({surr}, params, {}, /*retain_graph=*/c10::nullopt,
                                           /*create_graph=*/false, /*allow_unused=*/true),
                     params);
  }
  const double surr_before = surr.item<double>();

  // Fisher-vector product: d/dtheta (grad KL . v) at the current parameters.
  auto fisher = [&](const torch::Tensor& v) {
    const torch::Tensor kl = old.KlTo(PolicyOn(s)).mean();
    const std::vector<torch::Tensor> kl_grad = torch::autograd::grad(
        {kl}, params, {}, /*retain_graph=*/true, /*create_graph=*/true, /*allow_unused=*/true);
    const torch::Tensor gv = (FlatGradient(kl_grad, params) * v).sum();
    const torch::Tensor hv = FlatGradient(
        torch::autograd::grad({gv}, params, {}, c10::nullopt, false, /*allow_unused=*/true),
        params);
    return hv + trpo_.cg_damping * v;
  };
  m.Set("surrogate", surr_before);
  const TrustRegionResult step = TrustRegionStep(
      g, fisher, flat_values(), set_flat_values,
      [&] {
        torch::NoGradGuard no_grad;
        const nn::ActionDistribution d = PolicyOn(s);
        return std::make_pair(surrogate(d).item<double>(), old.KlTo(d).mean().item<double>());
      },
      surr_before, {trpo_.max_kl, trpo_.cg_iters, trpo_.backtrack_ratio, trpo_.max_backtracks});
  step.WriteTo(m);
  {
    torch::NoGradGuard no_grad;
    m.Set("entropy", PolicyOn(s).Entropy().mean().item<double>());
  }
  if (uses_value_network()) {
    m.Set("value_loss", FitValue(s, trpo_.vf_epochs, trpo_.vf_minibatch_size));
  }
  return m;
}

}  // namespace manyworlds::agents
