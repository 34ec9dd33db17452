// tanh for the hidden layers of the on-policy networks, about 6x faster than
// libtorch 1.13's (Sleef's 1-ulp AVX2 tanh took a fifth of a PPO epoch).
//
// |x| < 0.5625: x + x^3 R(x^2); above: 1 - 2 / (exp(2|x|) + 1) with exp by
// range reduction to [-ln2/2, ln2/2]; |x| >= 9.5 gives +-1. The polynomials
// are minimax fits made by scripts/fit_tanh_coefficients.py. Error: at most
// 1 ulp from the correctly rounded value over every float (checked once
// exhaustively; tests/nn/tanh_test.cc checks every 101st), as Sleef's; NaN stays
// NaN, -0 stays -0. Each element's result depends on its value only, never on
// its position or the tensor's length.
#ifndef MANYWORLDS_NN_TANH_H_
#define MANYWORLDS_NN_TANH_H_

#include <cstdint>

#include <torch/torch.h>

namespace manyworlds::nn {

// y[i] = tanh(x[i]) for i < n; x and y may be the same array.
void TanhKernel(const float* x, float* y, int64_t n);

// out[i] = grad[i] * (1 - y[i]^2): tanh's backward from its output y.
void TanhBackwardKernel(const float* grad, const float* y, float* out, int64_t n);

// tanh with autograd (backward: TanhBackwardKernel; libtorch's tanh_backward for
// a gradient that is not float32).
// float32 CPU tensors use TanhKernel; any other tensor goes to torch::tanh.
torch::Tensor Tanh(const torch::Tensor& x);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_TANH_H_
