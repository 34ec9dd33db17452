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
#include <string>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"
#include "manyworlds/nn/trunk.h"

namespace manyworlds::nn {

// Hidden-layer nonlinearity: ReLU (SAC family, MTRL) or tanh (garage's
// on-policy Gaussian MLP policies and value functions).
enum class Activation { kRelu, kTanh };

struct MlpOptions {
  int64_t input_dim = 0;
  int64_t output_dim = 0;
  int64_t hidden_dim = 400;
  int64_t num_layers = 3;  // hidden layers; 0 gives a single linear map
  int64_t ensemble_size = 1;  // EnsembleMlp only
  Activation activation = Activation::kRelu;
};

// Fills a 2-D tensor (or each matrix of a 3-D stack) with a (semi-)orthogonal
// matrix drawn from `generator` (the default CPU generator if none).
void InitOrthogonal(const torch::Tensor& weight, c10::optional<at::Generator> generator);

// Building blocks for networks that hold several MLPs in one flat buffer
// (task encoders, mixtures of encoders).
//
// Appends the layout of one MLP to `specs`, names prefixed by `prefix`
// (w0, b0, ...; torch parameter names may not contain dots); with
// `ensemble` true every shape gets a leading options.ensemble_size and
// biases a broadcast row. Returns the number of tensors appended
// (2 * (num_layers + 1)). Throws ConfigError on bad options.
size_t AppendMlpLayout(std::vector<ParamSpec>& specs, const std::string& prefix,
                       const MlpOptions& options, bool ensemble);
// Orthogonal weights, zero biases, for a (w, b, w, b, ...) list of views.
void InitMlpParams(at::ArrayRef<torch::Tensor> params, c10::optional<at::Generator> generator);
// Ensembles with at least this many rows run one addmm chain per member
// instead of one baddbmm per layer. Measured in PyTorch alone
// (bench/peers/ensemble_product.py, 2 vCPU, 300 wide): baddbmm is faster at
// 256 rows, level near 1,280, 10-20 % slower at 4,096 (forward + backward).
inline constexpr int64_t kEnsembleSplitRows = 2048;
// [Linear -> ReLU] x n -> Linear with params (w0, b0, ...) in [in, out]
// layout: x (..., in) -> (..., out) for 2-D weights; for 3-D (E, in, out)
// weights, x is (B, in) shared by all members or (E, B, in) -> (E, B, out).
torch::Tensor MlpForward(const torch::Tensor& x, at::ArrayRef<torch::Tensor> params,
                         Activation activation = Activation::kRelu);

// Multi-head outputs: `out` holds num_heads blocks of `head_dim` values in
// its last dimension, (B, num_heads * head_dim) or (E, B, num_heads *
// head_dim); returns the block of head[b] for each row b: (B, head_dim) or
// (E, B, head_dim). head: (B) int64 in [0, num_heads) (not range-checked).
torch::Tensor SelectHeads(const torch::Tensor& out, const torch::Tensor& head, int64_t head_dim);

// Mlp (kEnsemble false) and EnsembleMlp (true) share everything but the
// layout: one flat MLP, or ensemble_size of them stacked.
template <bool kEnsemble>
class BasicMlpImpl : public TrunkImpl {
 public:
  // Throws ConfigError on non-positive dims or negative num_layers.
  explicit BasicMlpImpl(const MlpOptions& options,
                        c10::optional<at::Generator> generator = c10::nullopt);

  // Mlp: x (B, input_dim) -> (B, output_dim). EnsembleMlp: x (B, input_dim),
  // shared by all members, or (E, B, input_dim), one input per member ->
  // (E, B, output_dim).
  torch::Tensor forward(const torch::Tensor& x) { return Forward(x, params()); }
  torch::Tensor Forward(const torch::Tensor& x) { return Forward(x, params()); }
  // Same network with explicit parameters (layout order of params());
  // Error if their number is wrong.
  torch::Tensor Forward(const torch::Tensor& x, at::ArrayRef<torch::Tensor> params) const;
  // The trunk form: an MLP ignores the task.
  torch::Tensor Forward(const torch::Tensor& x, const torch::Tensor& /*task*/,
                        at::ArrayRef<torch::Tensor> params) const override {
    return Forward(x, params);
  }

  const MlpOptions& options() const { return options_; }

 private:
  MlpOptions options_;
};
extern template class BasicMlpImpl<false>;
extern template class BasicMlpImpl<true>;

using MlpImpl = BasicMlpImpl<false>;
TORCH_MODULE(Mlp);
using EnsembleMlpImpl = BasicMlpImpl<true>;
TORCH_MODULE(EnsembleMlp);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_MLP_H_
