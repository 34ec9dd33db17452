#include "manyworlds/nn/stochastic_policy.h"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {
namespace {

constexpr double kLogSqrt2Pi = 0.91893853320467274178;  // log(sqrt(2 pi))

MlpOptions TrunkOptions(int64_t input_dim, int64_t output_dim, int64_t hidden_dim,
                        int64_t num_layers) {
  MlpOptions o;
  o.input_dim = input_dim;
  o.output_dim = output_dim;
  o.hidden_dim = hidden_dim;
  o.num_layers = num_layers;
  o.activation = Activation::kTanh;
  return o;
}

torch::Tensor PickHead(const torch::Tensor& out, const torch::Tensor& head, int64_t heads,
                       int64_t head_dim) {
  if (heads == 1) return out;
  if (!head.defined()) throw Error("multi-head network: a head index per row is required");
  return SelectHeads(out, head, head_dim);
}

}  // namespace

torch::Tensor ActionDistribution::LogProb(const torch::Tensor& actions) const {
  if (discrete) {
    const torch::Tensor index = actions.reshape({-1, 1}).to(torch::kInt64);
    return logits.gather(1, index).squeeze(1);
  }
  const torch::Tensor z = (actions - mean) * torch::exp(-log_std);
  return (-0.5 * z.square() - log_std - kLogSqrt2Pi).sum(-1);
}

torch::Tensor ActionDistribution::Entropy() const {
  if (discrete) return -(logits.exp() * logits).sum(-1);
  return (log_std + (0.5 + kLogSqrt2Pi)).sum(-1);
}

torch::Tensor ActionDistribution::KlTo(const ActionDistribution& other) const {
  if (discrete) return (logits.exp() * (logits - other.logits)).sum(-1);
  // KL(N(m1, s1) || N(m2, s2)) = log(s2/s1) + (s1^2 + (m1-m2)^2) / (2 s2^2) - 1/2
  const torch::Tensor var1 = torch::exp(2.0 * log_std);
  const torch::Tensor var2 = torch::exp(2.0 * other.log_std);
  return (other.log_std - log_std + (var1 + (mean - other.mean).square()) / (2.0 * var2) - 0.5)
      .sum(-1);
}

torch::Tensor ActionDistribution::Sample(at::Generator& generator) const {
  if (discrete) {
    return torch::multinomial(logits.exp(), 1, /*replacement=*/true, generator)
        .to(torch::kFloat32);
  }
  return mean + torch::exp(log_std) * torch::randn(mean.sizes(), generator, torch::kFloat32);
}

torch::Tensor ActionDistribution::Mode() const {
  if (discrete) return logits.argmax(1, /*keepdim=*/true).to(torch::kFloat32);
  return mean;
}

ActionDistribution ActionDistribution::Detached() const {
  ActionDistribution d;
  d.discrete = discrete;
  if (mean.defined()) d.mean = mean.detach();
  if (log_std.defined()) d.log_std = log_std.detach();
  if (logits.defined()) d.logits = logits.detach();
  return d;
}

void InitOnPolicyMlp(at::ArrayRef<torch::Tensor> params, double hidden_gain, double output_gain,
                     at::Generator& generator) {
  torch::NoGradGuard no_grad;
  for (size_t i = 0; i + 1 < params.size(); i += 2) {
    InitOrthogonal(params[i], generator);
    params[i].mul_(i + 2 < params.size() ? hidden_gain : output_gain);
    params[i + 1].zero_();
  }
}

StochasticPolicyImpl::StochasticPolicyImpl(const StochasticPolicyOptions& options,
                                           at::Generator& generator)
    : FlatModule("StochasticPolicy"), options_(options) {
  const auto& o = options_;
  if (o.input_dim <= 0 || o.num_heads <= 0 || (o.num_actions <= 0 && o.action_dim <= 0)) {
    throw ConfigError("policy: input_dim, action size and num_heads must be > 0");
  }
  if (o.num_actions <= 0 &&
      !(o.min_std > 0 && o.min_std <= o.init_std && o.init_std <= o.max_std &&
        std::isfinite(o.max_std))) {
    throw ConfigError("policy: need 0 < min_std <= init_std <= max_std < inf, got " +
                      std::to_string(o.min_std) + ", " + std::to_string(o.init_std) + ", " +
                      std::to_string(o.max_std));
  }
  head_dim_ = o.num_actions > 0 ? o.num_actions : o.action_dim;
  std::vector<ParamSpec> specs;
  mlp_tensors_ = AppendMlpLayout(
      specs, "", TrunkOptions(o.input_dim, head_dim_ * o.num_heads, o.hidden_dim, o.num_layers),
      false);
  if (!discrete()) specs.push_back({"log_std", {o.action_dim}});
  InitFlat(std::move(specs));
  const std::vector<torch::Tensor>& p = detached_params();
  InitOnPolicyMlp(at::ArrayRef<torch::Tensor>(p).slice(0, mlp_tensors_), std::sqrt(2.0),
                  o.output_gain, generator);
  if (!discrete()) {
    torch::NoGradGuard no_grad;
    p.back().fill_(std::log(o.init_std));
  }
}

ActionDistribution StochasticPolicyImpl::Forward(const torch::Tensor& x, const torch::Tensor& head,
                                                 at::ArrayRef<torch::Tensor> params) const {
  if (params.size() != mlp_tensors_ + (discrete() ? 0 : 1)) {
    throw Error("StochasticPolicy: expected " +
                std::to_string(mlp_tensors_ + (discrete() ? 0 : 1)) + " parameter tensors, got " +
                std::to_string(params.size()));
  }
  const torch::Tensor out =
      PickHead(MlpForward(x, params.slice(0, mlp_tensors_), Activation::kTanh), head,
               options_.num_heads, head_dim_);
  ActionDistribution d;
  d.discrete = discrete();
  if (d.discrete) {
    d.logits = torch::log_softmax(out, -1);
    return d;
  }
  d.mean = options_.tanh_mean ? torch::tanh(out) : out;
  const torch::Tensor log_std =
      params.back().clamp(std::log(options_.min_std), std::log(options_.max_std));
  d.log_std = log_std.expand_as(out);
  return d;
}

ValueNetworkImpl::ValueNetworkImpl(int64_t input_dim, int64_t hidden_dim, int64_t num_layers,
                                   int64_t num_heads, at::Generator& generator)
    : FlatModule("ValueNetwork"), num_heads_(num_heads) {
  if (num_heads <= 0) throw ConfigError("value network: num_heads must be > 0");
  std::vector<ParamSpec> specs;
  AppendMlpLayout(specs, "", TrunkOptions(input_dim, num_heads, hidden_dim, num_layers), false);
  InitFlat(std::move(specs));
  InitOnPolicyMlp(detached_params(), std::sqrt(2.0), 1.0, generator);
}

torch::Tensor ValueNetworkImpl::Forward(const torch::Tensor& x, const torch::Tensor& head,
                                        at::ArrayRef<torch::Tensor> params) const {
  return PickHead(MlpForward(x, params, Activation::kTanh), head, num_heads_, 1).squeeze(-1);
}

}  // namespace manyworlds::nn
