#include "manyworlds/nn/tanh.h"

#include <bit>
#include <cmath>
#include <cstdint>

// GCC tunes recent Intel CPUs for 256-bit vectors; on an AVX-512 Xeon the forward loop ran
// 1.33x faster with 512 (measured 2026-12-07). No effect without AVX-512; clang has no such
// target attribute.
#if defined(__GNUC__) && !defined(__clang__)
#define MANYWORLDS_WIDE_VECTORS __attribute__((target("prefer-vector-width=512")))
#else
#define MANYWORLDS_WIDE_VECTORS
#endif

namespace manyworlds::nn {
namespace {

// Below this |x| the odd polynomial is used; tanh(0.5625) is about 0.51, so
// the other branch's 1 - q never cancels more than one bit.
constexpr float kSmall = 0.5625f;
// tanh(9.5) rounds to 1.0f; beyond it exp would only grow.
constexpr float kSaturate = 9.5f;
// R(s), s = x^2: tanh(x) = x + x^3 R(s) on [0, kSmall].
constexpr float kT0 = -0x1.555548p-2f;
constexpr float kT1 = 0x1.110c72p-3f;
constexpr float kT2 = -0x1.b90948p-5f;
constexpr float kT3 = 0x1.582fb4p-6f;
constexpr float kT4 = -0x1.95002ep-8f;
// S(r): exp(r) = 1 + r + r^2 S(r) on [-ln2/2, ln2/2].
constexpr float kE0 = 0x1.fffffcp-2f;
constexpr float kE1 = 0x1.555492p-3f;
constexpr float kE2 = 0x1.5558f2p-5f;
constexpr float kE3 = 0x1.1239d4p-7f;
constexpr float kE4 = 0x1.6a2448p-10f;
constexpr float kLog2e = 0x1.715476p+0f;
// ln 2 split so that n * kLn2Hi is exact for the n used here (|n| < 2^8).
constexpr float kLn2Hi = 0x1.62e400p-1f;
constexpr float kLn2Lo = 0x1.7f7d1cp-20f;
// Adding and subtracting 1.5 * 2^23 rounds a float of magnitude < 2^22 to an integer.
constexpr float kRound = 0x1.8p23f;

inline float TanhOne(float x) {
  const float a = std::fabs(x);
  const float s = x * x;
  float r = kT4;
  r = r * s + kT3;
  r = r * s + kT2;
  r = r * s + kT1;
  r = r * s + kT0;
  const float small = a + a * s * r;
  // NaN compares false here and takes the small branch, which keeps it.
  const float z = 2.0f * (a < kSaturate ? a : kSaturate);
  const float n = (z * kLog2e + kRound) - kRound;
  const float t = (z - n * kLn2Hi) - n * kLn2Lo;
  float p = kE4;
  p = p * t + kE3;
  p = p * t + kE2;
  p = p * t + kE1;
  p = p * t + kE0;
  const float scale = std::bit_cast<float>((static_cast<int32_t>(n) + 127) << 23);
  const float e = (1.0f + t + t * t * p) * scale;
  const float large = 1.0f - 2.0f / (e + 1.0f);
  return std::copysign(a >= kSmall ? large : small, x);
}

class TanhFunction : public torch::autograd::Function<TanhFunction> {
 public:
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, const torch::Tensor& x) {
    const torch::Tensor in = x.contiguous();
    torch::Tensor y = torch::empty_like(in);
    TanhKernel(in.data_ptr<float>(), y.data_ptr<float>(), in.numel());
    ctx->save_for_backward({y});
    return y;
  }
  static torch::autograd::tensor_list backward(torch::autograd::AutogradContext* ctx,
                                               torch::autograd::tensor_list grads) {
    const torch::Tensor y = ctx->get_saved_variables()[0];
    // Under create_graph (TRPO's Hessian-vector products, MAML's inner steps) the backward must
    // itself be differentiable: libtorch's tanh_backward is. Otherwise the gradient is float32
    // and shaped like y, as autograd gives it for y.
    if (torch::GradMode::is_enabled()) return {at::tanh_backward(grads[0], y)};
    const torch::Tensor grad = grads[0].contiguous();
    torch::Tensor out = torch::empty_like(y);
    TanhBackwardKernel(grad.data_ptr<float>(), y.data_ptr<float>(), out.data_ptr<float>(),
                       y.numel());
    return {out};
  }
};

}  // namespace

MANYWORLDS_WIDE_VECTORS void TanhKernel(const float* x, float* y, int64_t n) {
  for (int64_t i = 0; i < n; ++i) y[i] = TanhOne(x[i]);
}

// libtorch 1.13's tanh_backward took 2.4x a multiplication's time in a PPO epoch.
MANYWORLDS_WIDE_VECTORS void TanhBackwardKernel(const float* grad, const float* y, float* out,
                                                int64_t n) {
  for (int64_t i = 0; i < n; ++i) out[i] = grad[i] * (1.0f - y[i] * y[i]);
}

torch::Tensor Tanh(const torch::Tensor& x) {
  if (x.scalar_type() != torch::kFloat32 || !x.device().is_cpu() || x.is_sparse()) {
    return torch::tanh(x);
  }
  return TanhFunction::apply(x);
}

}  // namespace manyworlds::nn
