#include "manyworlds/agents/deepmdp/latent_models.h"

#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/mlp.h"

namespace manyworlds::agents {
namespace {

constexpr double kLayerNormEps = 1e-5;

// Linear -> LayerNorm -> ReLU on params (w, b, ln_w, ln_b) from `first`.
torch::Tensor Hidden(const torch::Tensor& x, at::ArrayRef<torch::Tensor> p, int64_t width) {
  const torch::Tensor y = torch::addmm(p[1], x, p[0]);
  return torch::relu(torch::layer_norm(y, {width}, p[2], p[3], kLayerNormEps));
}

void InitLinear(const torch::Tensor& w, const torch::Tensor& b, at::Generator& generator) {
  nn::InitOrthogonal(w, generator);
  torch::NoGradGuard no_grad;
  b.zero_();
}

void InitNorm(const torch::Tensor& w, const torch::Tensor& b) {
  torch::NoGradGuard no_grad;
  w.fill_(1.0);
  b.zero_();
}

void CheckSizes(int64_t latent_dim, int64_t width, const char* what) {
  if (latent_dim < 1 || width < 1 || width > 65536) {
    throw ConfigError(std::string(what) + ": latent size must be >= 1 and width in [1, 65536], got " +
                      std::to_string(latent_dim) + " and " + std::to_string(width));
  }
}

}  // namespace

TransitionModelImpl::TransitionModelImpl(int64_t latent_dim, int64_t action_dim, int64_t width,
                                         bool probabilistic, at::Generator& generator)
    : FlatModule("TransitionModel"), width_(width), probabilistic_(probabilistic) {
  CheckSizes(latent_dim, width, "transition model");
  std::vector<nn::ParamSpec> specs = {{"fc_w", {latent_dim + action_dim, width}},
                                      {"fc_b", {width}},
                                      {"ln_w", {width}},
                                      {"ln_b", {width}},
                                      {"mu_w", {width, latent_dim}},
                                      {"mu_b", {latent_dim}}};
  if (probabilistic) {
    specs.push_back({"sigma_w", {width, latent_dim}});
    specs.push_back({"sigma_b", {latent_dim}});
  }
  InitFlat(std::move(specs));
  const auto& p = params();
  InitLinear(p[0], p[1], generator);
  InitNorm(p[2], p[3]);
  InitLinear(p[4], p[5], generator);
  if (probabilistic) InitLinear(p[6], p[7], generator);
}

std::pair<torch::Tensor, torch::Tensor> TransitionModelImpl::Forward(
    const torch::Tensor& x, at::ArrayRef<torch::Tensor> p) const {
  const torch::Tensor hidden = Hidden(x, p, width_);
  const torch::Tensor mu = torch::addmm(p[5], hidden, p[4]);
  if (!probabilistic_) return {mu, torch::Tensor()};
  const torch::Tensor sigma =
      kMinSigma + (kMaxSigma - kMinSigma) * torch::sigmoid(torch::addmm(p[7], hidden, p[6]));
  return {mu, sigma};
}

RewardDecoderImpl::RewardDecoderImpl(int64_t latent_dim, int64_t width, at::Generator& generator)
    : FlatModule("RewardDecoder"), width_(width) {
  CheckSizes(latent_dim, width, "reward decoder");
  InitFlat({{"fc_w", {latent_dim, width}},
            {"fc_b", {width}},
            {"ln_w", {width}},
            {"ln_b", {width}},
            {"out_w", {width, 1}},
            {"out_b", {1}}});
  const auto& p = params();
  InitLinear(p[0], p[1], generator);
  InitNorm(p[2], p[3]);
  InitLinear(p[4], p[5], generator);
}

torch::Tensor RewardDecoderImpl::Forward(const torch::Tensor& h,
                                         at::ArrayRef<torch::Tensor> p) const {
  return torch::addmm(p[5], Hidden(h, p, width_), p[4]).squeeze(1);
}

}  // namespace manyworlds::agents
