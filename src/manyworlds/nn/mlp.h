// Multi-layer perceptrons over one flat parameter buffer.
//
// Mlp: input -> [Linear -> ReLU] x num_layers -> Linear -> output, the
// MTRL/pytorch_sac `build_mlp` shape (num_layers counts hidden layers, so the
// MTRL default 3 x 400 has four linear maps). Weights are stored [in, out]
// so a layer is one addmm without a transpose.
//
// Besides Forward(x) every network has a functional Forward(x, params) that
// runs with an explicit parameter list in layout order (w0, b0, w1, b1, ...),
// e.g. MAML fast weights or detached_params() for a forward that needs input
// gradients but no weight gradients.
//
// EnsembleMlp: E independent MLPs of the same shape evaluated together, one
// baddbmm per layer over weights stacked [E, in, out]; twin critics are E=2.
//
// Initialisation follows pytorch_sac/MTRL: orthogonal weights, zero biases.
#ifndef MANYWORLDS_NN_MLP_H_
#define MANYWORLDS_NN_MLP_H_

#include <cstdint>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"

namespace manyworlds::nn {

struct MlpOptions {
  int64_t input_dim = 0;
  int64_t output_dim = 0;
  int64_t hidden_dim = 400;
  int64_t num_layers = 3;  // hidden layers; 0 gives a single linear map
  int64_t ensemble_size = 1;  // EnsembleMlp only
};

// Fills a 2-D tensor (or each matrix of a 3-D stack) with a (semi-)orthogonal
// matrix drawn from `generator` (the default CPU generator if none).
void InitOrthogonal(const torch::Tensor& weight, c10::optional<at::Generator> generator);

class MlpImpl : public FlatModule {
 public:
  // Throws ConfigError on non-positive dims or negative num_layers.
  explicit MlpImpl(const MlpOptions& options,
                   c10::optional<at::Generator> generator = c10::nullopt);

  // x: (B, input_dim) -> (B, output_dim).
  torch::Tensor forward(const torch::Tensor& x) { return Forward(x, params()); }
  torch::Tensor Forward(const torch::Tensor& x) { return Forward(x, params()); }
  // Same network with explicit parameters (layout order of params());
  // Error if their number is wrong.
  torch::Tensor Forward(const torch::Tensor& x, at::ArrayRef<torch::Tensor> params) const;

  const MlpOptions& options() const { return options_; }

 private:
  MlpOptions options_;
};
TORCH_MODULE(Mlp);

class EnsembleMlpImpl : public FlatModule {
 public:
  explicit EnsembleMlpImpl(const MlpOptions& options,
                           c10::optional<at::Generator> generator = c10::nullopt);

  // x: (B, input_dim), shared by all members, or (E, B, input_dim), one
  // input per member -> (E, B, output_dim).
  torch::Tensor forward(const torch::Tensor& x) { return Forward(x, params()); }
  torch::Tensor Forward(const torch::Tensor& x) { return Forward(x, params()); }
  torch::Tensor Forward(const torch::Tensor& x, at::ArrayRef<torch::Tensor> params) const;

  const MlpOptions& options() const { return options_; }

 private:
  MlpOptions options_;
};
TORCH_MODULE(EnsembleMlp);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_MLP_H_
