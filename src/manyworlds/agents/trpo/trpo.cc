#include "manyworlds/agents/trpo/trpo.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/pcgrad.h"

namespace manyworlds::agents {
namespace {

const TrpoConfig& Validated(const TrpoConfig& c) {
  c.Validate();
  return c;
}

// Gradients of `params` as one vector; a parameter the output does not
// depend on (undefined gradient) contributes zeros.
torch::Tensor Flatten(const std::vector<torch::Tensor>& parts,
                      const std::vector<torch::Tensor>& params) {
  std::vector<torch::Tensor> flat;
  flat.reserve(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) {
    flat.push_back(parts[i].defined() ? parts[i].reshape({-1})
                                      : torch::zeros({params[i].numel()}, params[i].options()));
  }
  return torch::cat(flat);
}

}  // namespace

void TrpoConfig::Validate() const {
  PolicyGradientConfig::Validate();
  auto fail = [](const char* field, const char* allowed, double value) {
    std::ostringstream msg;
    msg << "'agent." << field << "' must be " << allowed << ", got " << value;
    throw ConfigError(msg.str());
  };
  if (!(std::isfinite(max_kl) && max_kl > 0)) fail("max_kl", "finite and > 0", max_kl);
  if (cg_iters < 1 || cg_iters > 1000) fail("cg_iters", "in [1, 1000]", cg_iters);
  if (!(std::isfinite(cg_damping) && cg_damping >= 0)) fail("cg_damping", ">= 0", cg_damping);
  if (!(backtrack_ratio > 0 && backtrack_ratio < 1)) {
    fail("backtrack_ratio", "in (0, 1)", backtrack_ratio);
  }
  if (max_backtracks < 1 || max_backtracks > 1000) {
    fail("max_backtracks", "in [1, 1000]", max_backtracks);
  }
  if (vf_epochs < 0 || vf_epochs > 10000) fail("vf_epochs", "in [0, 10000]", vf_epochs);
  if (vf_minibatch_size < 1 || vf_minibatch_size > 100000000) {
    fail("vf_minibatch_size", "in [1, 1e8]", vf_minibatch_size);
  }
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
    int64_t offset = 0;
    for (const nn::FlatModule* m : modules) {
      m->flat().copy_(values.narrow(0, offset, m->num_params()));
      offset += m->num_params();
    }
  };
  const double regularizer =
      trpo_.entropy_method == "regularized" ? trpo_.entropy_coeff : 0.0;
  const nn::ActionDistribution old = PolicyOn(s).Detached();

  auto per_sample_surrogate = [&](const nn::ActionDistribution& d) {
    const torch::Tensor ratio = (d.LogProb(s.actions) - s.log_probs).exp();
    torch::Tensor value = ratio * s.advantages;
    if (regularizer > 0) value = value + regularizer * d.Entropy();
    return value;
  };
  auto surrogate = [&](const nn::ActionDistribution& d) {
    return per_sample_surrogate(d).mean();
  };

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
    g = Flatten(torch::autograd::grad({surr}, params, {}, /*retain_graph=*/c10::nullopt,
                                      /*create_graph=*/false, /*allow_unused=*/true),
                params);
  }
  const double surr_before = surr.item<double>();

  // Fisher-vector product: d/dtheta (grad KL . v) at the current parameters.
  auto fisher = [&](const torch::Tensor& v) {
    const torch::Tensor kl = old.KlTo(PolicyOn(s)).mean();
    const std::vector<torch::Tensor> kl_grad = torch::autograd::grad(
        {kl}, params, {}, /*retain_graph=*/true, /*create_graph=*/true, /*allow_unused=*/true);
    const torch::Tensor gv = (Flatten(kl_grad, params) * v).sum();
    const torch::Tensor hv = Flatten(torch::autograd::grad({gv}, params, {}, c10::nullopt,
                                                           false, /*allow_unused=*/true),
                                     params);
    return hv + trpo_.cg_damping * v;
  };
  const torch::Tensor direction = ConjugateGradient(fisher, g.detach(), trpo_.cg_iters);
  const double shs = direction.dot(fisher(direction)).item<double>();
  m.Set("surrogate", surr_before);
  double accepted_kl = 0.0;
  int64_t backtracks = trpo_.max_backtracks;
  bool accepted = false;
  if (shs > 0 && std::isfinite(shs)) {
    const torch::Tensor full_step = direction * std::sqrt(2.0 * trpo_.max_kl / shs);
    const torch::Tensor before = flat_values();
    torch::NoGradGuard no_grad;
    double fraction = 1.0;
    for (int64_t k = 0; k < trpo_.max_backtracks; ++k, fraction *= trpo_.backtrack_ratio) {
      set_flat_values(before + fraction * full_step);
      const nn::ActionDistribution d = PolicyOn(s);
      const double kl = old.KlTo(d).mean().item<double>();
      const double value = surrogate(d).item<double>();
      if (std::isfinite(kl) && kl <= trpo_.max_kl && value > surr_before) {
        accepted = true;
        accepted_kl = kl;
        backtracks = k;
        m.Set("surrogate_after", value);
        break;
      }
    }
    if (!accepted) set_flat_values(before);
  }
  m.Set("step_accepted", accepted ? 1.0 : 0.0);
  m.Set("backtracks", static_cast<double>(backtracks));
  m.Set("kl", accepted_kl);
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
