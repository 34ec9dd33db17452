#include "manyworlds/agents/trpo/trpo.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::agents {
namespace {

const TrpoConfig& Validated(const TrpoConfig& c) {
  c.Validate();
  return c;
}

torch::Tensor Flatten(const std::vector<torch::Tensor>& parts) {
  std::vector<torch::Tensor> flat;
  flat.reserve(parts.size());
  for (const torch::Tensor& p : parts) flat.push_back(p.reshape({-1}));
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
  const std::vector<torch::Tensor>& params = policy_->params();
  const double regularizer =
      trpo_.entropy_method == "regularized" ? trpo_.entropy_coeff : 0.0;
  const nn::ActionDistribution old = policy_->Forward(s.x, s.head).Detached();

  auto surrogate = [&](const nn::ActionDistribution& d) {
    const torch::Tensor ratio = (d.LogProb(s.actions) - s.log_probs).exp();
    torch::Tensor value = (ratio * s.advantages).mean();
    if (regularizer > 0) value = value + regularizer * d.Entropy().mean();
    return value;
  };

  const torch::Tensor surr = surrogate(policy_->Forward(s.x, s.head));
  const torch::Tensor g = Flatten(torch::autograd::grad({surr}, params));
  const double surr_before = surr.item<double>();

  // Fisher-vector product: d/dtheta (grad KL . v) at the current parameters.
  auto fisher = [&](const torch::Tensor& v) {
    const torch::Tensor kl = old.KlTo(policy_->Forward(s.x, s.head)).mean();
    const std::vector<torch::Tensor> kl_grad =
        torch::autograd::grad({kl}, params, {}, /*retain_graph=*/true, /*create_graph=*/true);
    const torch::Tensor gv = (Flatten(kl_grad) * v).sum();
    const torch::Tensor hv = Flatten(torch::autograd::grad({gv}, params));
    return hv + trpo_.cg_damping * v;
  };
  const torch::Tensor direction = ConjugateGradient(fisher, g.detach(), trpo_.cg_iters);
  const double shs = direction.dot(fisher(direction)).item<double>();
  Metrics m;
  m.Set("surrogate", surr_before);
  double accepted_kl = 0.0;
  int64_t backtracks = trpo_.max_backtracks;
  bool accepted = false;
  if (shs > 0 && std::isfinite(shs)) {
    const torch::Tensor full_step = direction * std::sqrt(2.0 * trpo_.max_kl / shs);
    const torch::Tensor before = policy_->flat().clone();
    torch::NoGradGuard no_grad;
    double fraction = 1.0;
    for (int64_t k = 0; k < trpo_.max_backtracks; ++k, fraction *= trpo_.backtrack_ratio) {
      policy_->flat().copy_(before + fraction * full_step);
      const nn::ActionDistribution d = policy_->Forward(s.x, s.head, policy_->detached_params());
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
    if (!accepted) policy_->flat().copy_(before);
  }
  m.Set("step_accepted", accepted ? 1.0 : 0.0);
  m.Set("backtracks", static_cast<double>(backtracks));
  m.Set("kl", accepted_kl);
  {
    torch::NoGradGuard no_grad;
    m.Set("entropy", policy_->Forward(s.x, s.head).Entropy().mean().item<double>());
  }
  if (uses_value_network()) {
    m.Set("value_loss", FitValue(s, trpo_.vf_epochs, trpo_.vf_minibatch_size));
  }
  return m;
}

}  // namespace manyworlds::agents
