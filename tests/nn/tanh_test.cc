// nn::Tanh, the on-policy networks' hidden activation: within 1 ulp of the correctly rounded
// tanh, odd, NaN-preserving, position-independent, and differentiated as tanh is.
#include "manyworlds/nn/tanh.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace manyworlds::nn {
namespace {

// Distance in representable floats (both finite, same sign convention).
int64_t Ulps(float a, float b) {
  auto ordered = [](float f) {
    const int32_t i = std::bit_cast<int32_t>(f);
    return i < 0 ? static_cast<int64_t>(std::numeric_limits<int32_t>::min()) - i
                 : static_cast<int64_t>(i);
  };
  return std::llabs(ordered(a) - ordered(b));
}

float Tanh1(float x) {
  float y;
  TanhKernel(&x, &y, 1);
  return y;
}

TEST(TanhTest, WithinOneUlpOfTheCorrectlyRoundedValue) {
  // Every 101st positive float from the smallest subnormal to the largest finite one (21M of
  // them; every float was checked once with a stride of 1), and each one's negative.
  std::vector<float> xs;
  for (uint32_t bits = 1; bits < 0x7f800000u; bits += 101) xs.push_back(std::bit_cast<float>(bits));
  std::vector<float> ys(xs.size()), negative_ys(xs.size()), negatives(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) negatives[i] = -xs[i];
  TanhKernel(xs.data(), ys.data(), static_cast<int64_t>(xs.size()));
  TanhKernel(negatives.data(), negative_ys.data(), static_cast<int64_t>(xs.size()));
  int64_t worst = 0;
  float worst_x = 0;
  for (size_t i = 0; i < xs.size(); ++i) {
    const auto reference = static_cast<float>(std::tanh(static_cast<double>(xs[i])));
    const int64_t ulps = Ulps(ys[i], reference);
    if (ulps > worst) {
      worst = ulps;
      worst_x = xs[i];
    }
    ASSERT_EQ(negative_ys[i], -ys[i]) << "not odd at " << xs[i];
  }
  EXPECT_LE(worst, 1) << "at x = " << worst_x;
}

TEST(TanhTest, SpecialValues) {
  EXPECT_TRUE(std::isnan(Tanh1(std::numeric_limits<float>::quiet_NaN())));
  EXPECT_TRUE(std::isnan(Tanh1(-std::numeric_limits<float>::quiet_NaN())));
  EXPECT_EQ(Tanh1(std::numeric_limits<float>::infinity()), 1.0f);
  EXPECT_EQ(Tanh1(-std::numeric_limits<float>::infinity()), -1.0f);
  EXPECT_EQ(Tanh1(9.02f), 1.0f);  // tanh(9.02) rounds to 1 in float
  EXPECT_EQ(Tanh1(1e30f), 1.0f);
  EXPECT_EQ(Tanh1(-3e38f), -1.0f);
  EXPECT_EQ(std::bit_cast<uint32_t>(Tanh1(0.0f)), std::bit_cast<uint32_t>(0.0f));
  EXPECT_EQ(std::bit_cast<uint32_t>(Tanh1(-0.0f)), std::bit_cast<uint32_t>(-0.0f));
  EXPECT_EQ(Tanh1(1e-30f), 1e-30f);
}

TEST(TanhTest, AnElementsValueDoesNotDependOnItsPositionOrTheLength) {
  // The vectorised loop and its scalar remainder must agree: same inputs at every offset and
  // length give the same outputs bit for bit.
  const torch::Tensor x = torch::randn({131}, at::detail::createCPUGenerator(3)) * 4;
  std::vector<float> reference(131);
  for (int64_t i = 0; i < 131; ++i) reference[i] = Tanh1(x[i].item<float>());
  for (int64_t offset = 0; offset < 17; ++offset) {
    for (int64_t length : {int64_t{1}, int64_t{7}, int64_t{33}, 131 - offset}) {
      std::vector<float> y(static_cast<size_t>(length));
      TanhKernel(x.data_ptr<float>() + offset, y.data(), length);
      for (int64_t i = 0; i < length; ++i) {
        ASSERT_EQ(std::bit_cast<uint32_t>(y[i]), std::bit_cast<uint32_t>(reference[offset + i]))
            << "offset " << offset << " length " << length << " element " << i;
      }
    }
  }
}

TEST(TanhTest, BackwardKernelIsTheGradientFromTheOutput) {
  const std::vector<float> grad = {1.0f, -2.0f, 0.5f, 3.0f};
  const std::vector<float> y = {0.0f, 0.5f, -0.9f, 1.0f};
  std::vector<float> out(4);
  TanhBackwardKernel(grad.data(), y.data(), out.data(), 4);
  EXPECT_EQ(out[0], 1.0f);
  EXPECT_FLOAT_EQ(out[1], -1.5f);
  EXPECT_FLOAT_EQ(out[2], 0.5f * (1.0f - 0.81f));
  EXPECT_EQ(out[3], 0.0f);
}

TEST(TanhTest, ForwardAndGradientMatchLibtorchs) {
  at::Generator g = at::detail::createCPUGenerator(5);
  const torch::Tensor base = torch::randn({64, 48}, g) * 3;
  // a transposed (non-contiguous) input as the networks never give, to cover the copy
  const torch::Tensor x = base.t().clone().t().requires_grad_(true);
  const torch::Tensor reference_x = base.clone().requires_grad_(true);
  const torch::Tensor upstream = torch::randn({64, 48}, g);
  const torch::Tensor y = Tanh(x);
  const torch::Tensor reference_y = torch::tanh(reference_x);
  EXPECT_LE((y - reference_y).abs().max().item<float>(), 1.2e-7f);
  (y * upstream).sum().backward();
  (reference_y * upstream).sum().backward();
  // the same formula on outputs within an ulp
  EXPECT_TRUE(torch::allclose(x.grad(), reference_x.grad(), 0, 1e-6));
  EXPECT_TRUE(x.grad().abs().sum().item<float>() > 0);
}

TEST(TanhTest, SecondDerivativesMatchLibtorchs) {
  // TRPO's Hessian-vector products and MAML's inner steps differentiate the backward again.
  at::Generator g = at::detail::createCPUGenerator(7);
  const torch::Tensor base = torch::randn({32, 16}, g) * 2;
  const torch::Tensor v = torch::randn({32, 16}, g);
  auto hessian_vector = [&](auto tanh) {
    const torch::Tensor x = base.clone().requires_grad_(true);
    const torch::Tensor y = tanh(x);
    const torch::Tensor loss = (y * y * v).sum();
    const torch::Tensor grad = torch::autograd::grad({loss}, {x}, {}, true, true)[0];
    return torch::autograd::grad({(grad * v).sum()}, {x})[0];
  };
  const torch::Tensor ours = hessian_vector([](const torch::Tensor& x) { return Tanh(x); });
  const torch::Tensor reference = hessian_vector([](const torch::Tensor& x) { return torch::tanh(x); });
  EXPECT_GT(reference.abs().max().item<float>(), 0.1f);
  EXPECT_TRUE(torch::allclose(ours, reference, 1e-5, 1e-5))
      << (ours - reference).abs().max().item<float>();
}

TEST(TanhTest, OtherTypesAndGradModesUseLibtorchOrNoGraph) {
  const torch::Tensor d = torch::linspace(-5, 5, 11, torch::kDouble);
  EXPECT_TRUE(torch::equal(Tanh(d), torch::tanh(d)));
  {
    c10::InferenceMode inference;
    const torch::Tensor y = Tanh(torch::ones({3}));
    EXPECT_FALSE(y.requires_grad());
    EXPECT_NEAR(y[0].item<float>(), std::tanh(1.0f), 1e-7);
  }
  torch::NoGradGuard no_grad;
  EXPECT_FALSE(Tanh(torch::ones({3}, torch::requires_grad())).requires_grad());
}

}  // namespace
}  // namespace manyworlds::nn
