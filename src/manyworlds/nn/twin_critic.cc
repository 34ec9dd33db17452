#include "manyworlds/nn/twin_critic.h"

#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/flat_optim.h"

namespace manyworlds::nn {
namespace {

// (2, B, heads) -> (2, B): the head of each row.
torch::Tensor Heads(const torch::Tensor& out, const torch::Tensor& head, int64_t num_heads) {
  if (num_heads == 1) return out.squeeze(-1);
  if (!head.defined()) throw Error("TwinCritic: a multi-head forward needs head indices");
  return SelectHeads(out, head, 1).squeeze(-1);
}

}  // namespace

TwinCriticImpl::TwinCriticImpl(const TwinCriticOptions& options,
                               c10::optional<at::Generator> generator)
    : torch::nn::Module("TwinCritic"), options_(options) {
  MlpOptions mlp;
  mlp.input_dim = options.obs_dim + options.action_dim;
  if (options.num_heads <= 0) {
    throw ConfigError("TwinCritic: num_heads must be > 0, got " +
                      std::to_string(options.num_heads));
  }
  mlp.output_dim = options.num_heads;
  mlp.hidden_dim = options.hidden_dim;
  mlp.num_layers = options.num_layers;
  mlp.ensemble_size = 2;
  Init([&mlp](c10::optional<at::Generator> g) { return std::make_shared<EnsembleMlpImpl>(mlp, g); },
       generator);
}

TwinCriticImpl::TwinCriticImpl(const TwinCriticOptions& options, const TrunkFactory& make_trunk,
                               c10::optional<at::Generator> generator)
    : torch::nn::Module("TwinCritic"), options_(options) {
  if (options.num_heads <= 0) {
    throw ConfigError("TwinCritic: num_heads must be > 0, got " +
                      std::to_string(options.num_heads));
  }
  Init(make_trunk, generator);
}

void TwinCriticImpl::Init(const TrunkFactory& make_trunk, c10::optional<at::Generator> generator) {
  online_ = register_module("online", make_trunk(generator));
  target_ = register_module("target", make_trunk(generator));
  target_->CopyFrom(*online_);
  // The target is never trained: no gradients, and the optimizer skips it.
  for (const torch::Tensor& p : target_->params()) p.requires_grad_(false);
}

torch::Tensor TwinCriticImpl::Q(const torch::Tensor& obs, const torch::Tensor& action,
                                const torch::Tensor& head,
                                at::ArrayRef<torch::Tensor> params) const {
  return Heads(online_->Forward(torch::cat({obs, action}, -1), head, params), head,
               options_.num_heads);
}

torch::Tensor TwinCriticImpl::TargetQ(const torch::Tensor& obs, const torch::Tensor& action,
                                      const torch::Tensor& head) const {
  return Heads(
      target_->Forward(torch::cat({obs, action}, -1), head, target_->detached_params()), head,
      options_.num_heads);
}

void TwinCriticImpl::UpdateTarget(double tau) {
  PolyakUpdate(target_->flat(), online_->flat(), tau);
}

}  // namespace manyworlds::nn
