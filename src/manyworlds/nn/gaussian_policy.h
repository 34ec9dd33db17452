// Tanh-squashed diagonal Gaussian policy (SAC).
//
// The trunk (an Mlp) outputs 2*A values: the mean of u and a raw log-std
// that goes through tanh and is rescaled to [log_std_min, log_std_max]
// (MTRL/pytorch_sac; default [-20, 2]). The action is a = tanh(u) with
// u ~ N(mean, std^2), so it lies in (-1, 1); callers rescale to the env's
// bounds. The log-density of a includes the change of variables,
//   log p(a) = log N(u) - sum_i log(1 - tanh(u_i)^2),
// with log(1 - tanh(u)^2) = 2 (log 2 - u - softplus(-2u)), which stays finite
// where 1 - tanh(u)^2 underflows in float.
//
// With num_heads > 1 the last linear map holds one output head per task
// (MTRL's multi-head policy): the trunk computes all heads as one product,
// (B, num_heads * 2A), and each row keeps the head named by `head` (B).
//
// The trunk can also be any TrunkImpl (trunk.h) with 2A * num_heads
// outputs, e.g. a Soft Modularization, PaCo or MOORE network; `head` is then
// the task index it routes by.
#ifndef MANYWORLDS_NN_GAUSSIAN_POLICY_H_
#define MANYWORLDS_NN_GAUSSIAN_POLICY_H_

#include <cstdint>

#include <torch/torch.h>

#include "manyworlds/nn/mlp.h"
#include "manyworlds/nn/trunk.h"

namespace manyworlds::nn {

// log|d tanh(u)/du| summed over the last dimension: (..., A) -> (...).
torch::Tensor TanhLogAbsDetJacobian(const torch::Tensor& u);

// log N(u; mean, exp(log_std)^2) summed over the last dimension.
torch::Tensor DiagGaussianLogProb(const torch::Tensor& u, const torch::Tensor& mean,
                                  const torch::Tensor& log_std);

// Maps raw values to [min, max] through tanh (smooth, keeps gradients).
torch::Tensor BoundLogStd(const torch::Tensor& raw, double log_std_min, double log_std_max);

struct SquashedSample {
  torch::Tensor action;    // (B, A), tanh(u)
  torch::Tensor log_prob;  // (B), log-density of action
  torch::Tensor pre_tanh;  // (B, A), u (another policy's density of the action needs it)
};

// Reparameterised sample (u = mean + std * eps, differentiable in mean and
// log_std) with its log-probability.
SquashedSample SampleSquashedGaussian(const torch::Tensor& mean, const torch::Tensor& log_std,
                                      c10::optional<at::Generator> generator = c10::nullopt);
// The same with the standard normal noise eps (shape of mean) given, e.g.
// drawn for a whole batch before it is split across threads.
SquashedSample SquashedGaussianFromNoise(const torch::Tensor& mean, const torch::Tensor& log_std,
                                         const torch::Tensor& eps);

struct GaussianPolicyOptions {
  int64_t obs_dim = 0;
  int64_t action_dim = 0;
  int64_t hidden_dim = 400;
  int64_t num_layers = 3;
  double log_std_min = -20.0;
  double log_std_max = 2.0;
  int64_t num_heads = 1;  // output heads; a forward then needs a head index
};

struct PolicyOutput {
  torch::Tensor mean;     // (B, A), mean of the pre-tanh Gaussian
  torch::Tensor log_std;  // (B, A), already bounded
};

class GaussianPolicyImpl : public torch::nn::Module {
 public:
  // Throws ConfigError on bad dims or log_std_min >= log_std_max.
  explicit GaussianPolicyImpl(const GaussianPolicyOptions& options,
                              c10::optional<at::Generator> generator = c10::nullopt);
  // With a trunk from make_trunk (options.hidden_dim and num_layers unused);
  // ConfigError unless its output is 2 * action_dim * num_heads wide.
  GaussianPolicyImpl(const GaussianPolicyOptions& options, const TrunkFactory& make_trunk,
                     int64_t trunk_output_dim, c10::optional<at::Generator> generator);

  // obs: (B, obs_dim); head: (B) int64 in [0, num_heads), required when
  // num_heads > 1 and ignored (may be undefined) otherwise.
  PolicyOutput forward(const torch::Tensor& obs, const torch::Tensor& head = {}) {
    return Forward(obs, head, trunk_->params());
  }
  PolicyOutput Forward(const torch::Tensor& obs, const torch::Tensor& head,
                       at::ArrayRef<torch::Tensor> params) const;
  SquashedSample Sample(const torch::Tensor& obs, c10::optional<at::Generator> generator,
                        const torch::Tensor& head = {});
  // tanh(mean): the evaluation action.
  torch::Tensor MeanAction(const torch::Tensor& obs, const torch::Tensor& head = {});

  // The network holding all parameters (flat buffer, functional forward).
  const std::shared_ptr<TrunkImpl>& trunk() const { return trunk_; }
  const GaussianPolicyOptions& options() const { return options_; }

 private:
  GaussianPolicyOptions options_;
  void CheckOptions() const;
  std::shared_ptr<TrunkImpl> trunk_;
};
TORCH_MODULE(GaussianPolicy);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_GAUSSIAN_POLICY_H_
