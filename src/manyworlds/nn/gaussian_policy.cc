#include "manyworlds/nn/gaussian_policy.h"

#include <cmath>
#include <numbers>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {

torch::Tensor TanhLogAbsDetJacobian(const torch::Tensor& u) {
  // 1 - tanh(u)^2 = 4 / (e^u + e^-u)^2, whose log is 2 (log 2 - u - softplus(-2u)).
  const double log2 = std::log(2.0);
  return (2.0 * (log2 - u - torch::softplus(-2.0 * u))).sum(-1);
}

torch::Tensor DiagGaussianLogProb(const torch::Tensor& u, const torch::Tensor& mean,
                                  const torch::Tensor& log_std) {
  const double half_log_2pi = 0.5 * std::log(2.0 * std::numbers::pi);
  torch::Tensor z = (u - mean) * torch::exp(-log_std);
  return (-0.5 * z.square() - log_std - half_log_2pi).sum(-1);
}

torch::Tensor BoundLogStd(const torch::Tensor& raw, double log_std_min, double log_std_max) {
  return log_std_min + 0.5 * (log_std_max - log_std_min) * (torch::tanh(raw) + 1.0);
}

SquashedSample SampleSquashedGaussian(const torch::Tensor& mean, const torch::Tensor& log_std,
                                      c10::optional<at::Generator> generator) {
  return SquashedGaussianFromNoise(mean, log_std,
                                   torch::randn(mean.sizes(), generator, mean.options()));
}

SquashedSample SquashedGaussianFromNoise(const torch::Tensor& mean, const torch::Tensor& log_std,
                                         const torch::Tensor& eps) {
  if (!eps.sizes().equals(mean.sizes())) {
    throw Error("SquashedGaussianFromNoise: eps must have the shape of mean");
  }
  torch::Tensor u = mean + eps * log_std.exp();
  // log N(u) written with eps directly: (u - mean) / std is exactly eps.
  const double half_log_2pi = 0.5 * std::log(2.0 * std::numbers::pi);
  torch::Tensor log_prob = (-0.5 * eps.square() - log_std - half_log_2pi).sum(-1);
  return {torch::tanh(u), log_prob - TanhLogAbsDetJacobian(u), u};
}

GaussianPolicyImpl::GaussianPolicyImpl(const GaussianPolicyOptions& options,
                                       c10::optional<at::Generator> generator)
    : torch::nn::Module("GaussianPolicy"), options_(options) {
  CheckOptions();
  MlpOptions trunk;
  trunk.input_dim = options.obs_dim;
  trunk.output_dim = 2 * options.action_dim * options.num_heads;
  trunk.hidden_dim = options.hidden_dim;
  trunk.num_layers = options.num_layers;
  trunk_ = register_module("trunk", std::make_shared<MlpImpl>(trunk, generator));
}

GaussianPolicyImpl::GaussianPolicyImpl(const GaussianPolicyOptions& options,
                                       const TrunkFactory& make_trunk, int64_t trunk_output_dim,
                                       c10::optional<at::Generator> generator)
    : torch::nn::Module("GaussianPolicy"), options_(options) {
  CheckOptions();
  if (trunk_output_dim != 2 * options.action_dim * options.num_heads) {
    throw ConfigError("GaussianPolicy: the trunk has " + std::to_string(trunk_output_dim) +
                      " outputs, the policy needs 2 * action_dim * num_heads = " +
                      std::to_string(2 * options.action_dim * options.num_heads));
  }
  trunk_ = register_module("trunk", make_trunk(generator));
}

void GaussianPolicyImpl::CheckOptions() const {
  const GaussianPolicyOptions& options = options_;
  if (options.action_dim <= 0) {
    throw ConfigError("GaussianPolicy: action_dim must be > 0, got " +
                      std::to_string(options.action_dim));
  }
  if (options.num_heads <= 0) {
    throw ConfigError("GaussianPolicy: num_heads must be > 0, got " +
                      std::to_string(options.num_heads));
  }
  if (!(options.log_std_min < options.log_std_max)) {
    throw ConfigError("GaussianPolicy: log_std_min must be < log_std_max");
  }
}

PolicyOutput GaussianPolicyImpl::Forward(const torch::Tensor& obs, const torch::Tensor& head,
                                         at::ArrayRef<torch::Tensor> params) const {
  const int64_t a = options_.action_dim;
  torch::Tensor out = trunk_->Forward(obs, head, params);
  if (options_.num_heads > 1) {
    if (!head.defined()) throw Error("GaussianPolicy: a multi-head forward needs head indices");
    out = SelectHeads(out, head, 2 * a);
  }
  return {out.narrow(-1, 0, a),
          BoundLogStd(out.narrow(-1, a, a), options_.log_std_min, options_.log_std_max)};
}

SquashedSample GaussianPolicyImpl::Sample(const torch::Tensor& obs,
                                          c10::optional<at::Generator> generator,
                                          const torch::Tensor& head) {
  PolicyOutput out = forward(obs, head);
  return SampleSquashedGaussian(out.mean, out.log_std, generator);
}

torch::Tensor GaussianPolicyImpl::MeanAction(const torch::Tensor& obs, const torch::Tensor& head) {
  return torch::tanh(forward(obs, head).mean);
}

}  // namespace manyworlds::nn
