#include "manyworlds/nn/twin_critic.h"

#include "manyworlds/nn/flat_optim.h"

namespace manyworlds::nn {

TwinCriticImpl::TwinCriticImpl(const TwinCriticOptions& options,
                               c10::optional<at::Generator> generator)
    : torch::nn::Module("TwinCritic"), options_(options) {
  MlpOptions mlp;
  mlp.input_dim = options.obs_dim + options.action_dim;
  mlp.output_dim = 1;
  mlp.hidden_dim = options.hidden_dim;
  mlp.num_layers = options.num_layers;
  mlp.ensemble_size = 2;
  online_ = register_module("online", EnsembleMlp(mlp, generator));
  target_ = register_module("target", EnsembleMlp(mlp, generator));
  target_->CopyFrom(*online_);
  // The target is never trained: no gradients, and the optimizer skips it.
  for (const torch::Tensor& p : target_->params()) p.requires_grad_(false);
}

torch::Tensor TwinCriticImpl::Q(const torch::Tensor& obs, const torch::Tensor& action,
                                at::ArrayRef<torch::Tensor> params) const {
  return online_->Forward(torch::cat({obs, action}, -1), params).squeeze(-1);
}

torch::Tensor TwinCriticImpl::TargetQ(const torch::Tensor& obs,
                                      const torch::Tensor& action) const {
  return target_->Forward(torch::cat({obs, action}, -1), target_->detached_params())
      .squeeze(-1);
}

void TwinCriticImpl::UpdateTarget(double tau) {
  PolyakUpdate(target_->flat(), online_->flat(), tau);
}

}  // namespace manyworlds::nn
