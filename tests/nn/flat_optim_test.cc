#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/flat_optim.h"

namespace manyworlds::nn {
namespace {

// Max |a - b| / max |b|, the relative error of a whole buffer.
double RelativeError(const torch::Tensor& a, const torch::Tensor& b) {
  return ((a - b).abs().max() / b.abs().max()).item<double>();
}

void CompareWithTorchAdam(const AdamOptions& options) {
  torch::manual_seed(17);
  const int64_t n = 1000;
  torch::Tensor flat = torch::randn({n});
  torch::Tensor reference = flat.clone().requires_grad_();
  torch::optim::Adam torch_adam({reference}, torch::optim::AdamOptions(options.lr)
                                                 .betas({options.beta1, options.beta2})
                                                 .eps(options.eps)
                                                 .weight_decay(options.weight_decay));
  FlatAdam adam(n, options);
  for (int step = 0; step < 20; ++step) {
    // Grads over several magnitudes, including exact zeros.
    torch::Tensor grad = torch::randn({n}) * std::pow(10.0, step % 4 - 2);
    grad.narrow(0, 0, 10).zero_();
    reference.mutable_grad() = grad.clone();
    torch_adam.step();
    adam.Step(flat, grad);
  }
  EXPECT_EQ(adam.step(), 20);
  EXPECT_LT(RelativeError(flat, reference.detach()), 1e-6);
  EXPECT_TRUE(torch::allclose(flat, reference.detach(), 1e-6, 1e-6));
}

TEST(FlatAdamTest, MatchesTorchAdamOver20Steps) { CompareWithTorchAdam(AdamOptions{}); }

TEST(FlatAdamTest, MatchesTorchAdamWithWeightDecayAndOtherBetas) {
  AdamOptions options;
  options.lr = 1e-2;
  options.beta1 = 0.5;
  options.beta2 = 0.9;
  options.eps = 1e-6;
  options.weight_decay = 0.01;
  CompareWithTorchAdam(options);
}

TEST(FlatAdamTest, StateRoundTripsThroughAnArchive) {
  const int64_t n = 50;
  FlatAdam a(n, AdamOptions{});
  torch::Tensor p = torch::randn({n});
  for (int i = 0; i < 3; ++i) a.Step(p, torch::randn({n}));
  torch::serialize::OutputArchive out;
  a.Save(out);
  std::stringstream stream;
  out.save_to(stream);

  FlatAdam b(n, AdamOptions{});
  torch::serialize::InputArchive in;
  in.load_from(stream);
  b.Load(in);
  EXPECT_EQ(b.step(), 3);
  EXPECT_TRUE(torch::equal(a.exp_avg(), b.exp_avg()));
  EXPECT_TRUE(torch::equal(a.exp_avg_sq(), b.exp_avg_sq()));
  // Both continue identically.
  torch::Tensor g = torch::randn({n});
  torch::Tensor p2 = p.clone();
  a.Step(p, g);
  b.Step(p2, g);
  EXPECT_TRUE(torch::equal(p, p2));

  FlatAdam wrong(n + 1, AdamOptions{});
  stream.seekg(0);
  torch::serialize::InputArchive in2;
  in2.load_from(stream);
  EXPECT_THROW(wrong.Load(in2), Error);
}

TEST(FlatAdamTest, RejectsBadOptionsAndBuffers) {
  AdamOptions bad;
  bad.beta1 = 1.0;
  EXPECT_THROW(FlatAdam(3, bad), ConfigError);
  FlatAdam adam(3, AdamOptions{});
  EXPECT_THROW(adam.Step(torch::zeros({4}), torch::zeros({4})), Error);
  EXPECT_THROW(adam.Step(torch::zeros({3}, torch::kFloat64), torch::zeros({3})), Error);
}

TEST(PolyakUpdateTest, MatchesHandComputedValues) {
  torch::Tensor target = torch::tensor({1.0f, -2.0f, 0.5f, 4.0f});
  torch::Tensor source = torch::tensor({3.0f, 2.0f, 0.5f, -4.0f});
  PolyakUpdate(target, source, 0.25);
  // 0.75 t + 0.25 s
  const std::vector<float> expected = {1.5f, -1.0f, 0.5f, 2.0f};
  for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(target[i].item<float>(), expected[i]);
  PolyakUpdate(target, source, 1.0);
  EXPECT_TRUE(torch::equal(target, source));
  PolyakUpdate(target, torch::zeros({4}), 0.0);
  EXPECT_TRUE(torch::equal(target, source));
  EXPECT_THROW(PolyakUpdate(target, source, 1.5), Error);
  EXPECT_THROW(PolyakUpdate(target, torch::zeros({3}), 0.1), Error);
}

}  // namespace
}  // namespace manyworlds::nn
