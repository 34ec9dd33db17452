// Twin Q critics Q(s, a) with target copies, evaluated as one batched
// product per layer (an EnsembleMlp of size 2 over concat(obs, action)).
// With num_heads > 1 each critic's last linear map holds one Q head per task
// (MTRL's multi-head critic), all heads computed as one product and the head
// of each row chosen by `head` (B).
//
// The pair can also be any 2-member TrunkImpl (trunk.h) over concat(obs,
// action) with num_heads outputs per member, e.g. a Soft Modularization, PaCo
// or MOORE ensemble; `head` is then the task index it routes by.
#ifndef MANYWORLDS_NN_TWIN_CRITIC_H_
#define MANYWORLDS_NN_TWIN_CRITIC_H_

#include <cstdint>

#include <torch/torch.h>

#include "manyworlds/nn/mlp.h"
#include "manyworlds/nn/trunk.h"

namespace manyworlds::nn {

struct TwinCriticOptions {
  int64_t obs_dim = 0;
  int64_t action_dim = 0;
  int64_t hidden_dim = 400;
  int64_t num_layers = 3;
  int64_t num_heads = 1;
};

class TwinCriticImpl : public torch::nn::Module {
 public:
  // The target starts as a copy of the online critics.
  explicit TwinCriticImpl(const TwinCriticOptions& options,
                          c10::optional<at::Generator> generator = c10::nullopt);
  // Online and target from make_trunk (hidden_dim, num_layers unused): each
  // must map (B, obs_dim + action_dim) to (2, B, num_heads).
  TwinCriticImpl(const TwinCriticOptions& options, const TrunkFactory& make_trunk,
                 c10::optional<at::Generator> generator);

  // obs (B, obs_dim), action (B, action_dim) -> (2, B), both online critics.
  // head: (B) int64 in [0, num_heads), required when num_heads > 1 and
  // ignored (may be undefined) otherwise.
  torch::Tensor forward(const torch::Tensor& obs, const torch::Tensor& action,
                        const torch::Tensor& head = {}) {
    return Q(obs, action, head, online_->params());
  }
  // With explicit parameters, e.g. online()->detached_params() for an actor
  // loss that must not produce critic weight gradients.
  torch::Tensor Q(const torch::Tensor& obs, const torch::Tensor& action, const torch::Tensor& head,
                  at::ArrayRef<torch::Tensor> params) const;
  // Target critics; call under NoGradGuard / InferenceMode. (2, B).
  torch::Tensor TargetQ(const torch::Tensor& obs, const torch::Tensor& action,
                        const torch::Tensor& head = {}) const;
  // target <- (1 - tau) target + tau online, one loop over the flat buffers.
  void UpdateTarget(double tau);

  const std::shared_ptr<TrunkImpl>& online() const { return online_; }
  const std::shared_ptr<TrunkImpl>& target() const { return target_; }
  const TwinCriticOptions& options() const { return options_; }

 private:
  TwinCriticOptions options_;
  void Init(const TrunkFactory& make_trunk, c10::optional<at::Generator> generator);
  std::shared_ptr<TrunkImpl> online_;
  std::shared_ptr<TrunkImpl> target_;
};
TORCH_MODULE(TwinCritic);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_TWIN_CRITIC_H_
