// DeepMDP's latent models (MTRL's agent/components/transition_model.py and
// reward_decoder.py): functions of the encoder's latent h.
//
// TransitionModel: [h, a] -> Linear(width) -> LayerNorm -> ReLU -> Linear(H)
// for the mean of the next latent; probabilistic models add a second head
// for its standard deviation, sigmoid-mapped into [min_sigma, max_sigma]
// (MTRL's 1e-4 and 10); deterministic ones have sigma = 1.
// RewardDecoder: h -> Linear(width) -> LayerNorm -> ReLU -> Linear(1).
// Initialisation: orthogonal weights, zero biases (our MLPs' rule).
#ifndef MANYWORLDS_AGENTS_DEEPMDP_LATENT_MODELS_H_
#define MANYWORLDS_AGENTS_DEEPMDP_LATENT_MODELS_H_

#include <cstdint>
#include <utility>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"

namespace manyworlds::agents {

class TransitionModelImpl : public nn::FlatModule {
 public:
  TransitionModelImpl(int64_t latent_dim, int64_t action_dim, int64_t width, bool probabilistic,
                      at::Generator& generator);
  // (mean, sigma) of the next latent for x = [h, a] (B, H + A); sigma is
  // undefined for a deterministic model.
  std::pair<torch::Tensor, torch::Tensor> Forward(const torch::Tensor& x,
                                                  at::ArrayRef<torch::Tensor> params) const;
  bool probabilistic() const { return probabilistic_; }

  static constexpr double kMinSigma = 1e-4;
  static constexpr double kMaxSigma = 10.0;

 private:
  int64_t width_;
  bool probabilistic_;
};
TORCH_MODULE(TransitionModel);

class RewardDecoderImpl : public nn::FlatModule {
 public:
  RewardDecoderImpl(int64_t latent_dim, int64_t width, at::Generator& generator);
  // h (B, H) -> (B)
  torch::Tensor Forward(const torch::Tensor& h, at::ArrayRef<torch::Tensor> params) const;

 private:
  int64_t width_;
};
TORCH_MODULE(RewardDecoder);

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_DEEPMDP_LATENT_MODELS_H_
