// A one-layer GRU over a flat parameter buffer (RL2's recurrent policy).
//
// Parameters in torch::nn::GRU's layout (w_ih (3H, in), w_hh (3H, H), b_ih,
// b_hh; gates r, z, n), initialised as torch does: U(-1/sqrt(H), 1/sqrt(H)),
// from the generator. Forward runs ATen's fused GRU over a whole sequence;
// a single step is a sequence of length 1, so acting and training compute
// the same function with the same kernels.
#ifndef MANYWORLDS_NN_GRU_H_
#define MANYWORLDS_NN_GRU_H_

#include <cstdint>
#include <utility>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"

namespace manyworlds::nn {

class GruImpl : public FlatModule {
 public:
  // Throws ConfigError on non-positive sizes.
  GruImpl(int64_t input_dim, int64_t hidden_dim, at::Generator& generator);

  // x (T, N, input_dim), h0 (N, hidden_dim) -> (outputs (T, N, H), h_T (N, H)).
  std::pair<torch::Tensor, torch::Tensor> Forward(const torch::Tensor& x,
                                                  const torch::Tensor& h0) const;

  int64_t input_dim() const { return input_dim_; }
  int64_t hidden_dim() const { return hidden_dim_; }

 private:
  int64_t input_dim_, hidden_dim_;
};
TORCH_MODULE(Gru);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_GRU_H_
