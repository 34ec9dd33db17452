// libtorch's float products on oneDNN (nn/preinit/gemm_onednn.cc): every transpose, stride and
// accumulation libtorch hands to sgemm_ gives the product, within float rounding of a double
// reference, and a product repeats bit for bit.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/nn/threads.h"

namespace manyworlds::nn {
namespace {

// Largest difference from the product in double precision, relative to the largest entry.
double RelativeError(const torch::Tensor& ours, const torch::Tensor& reference) {
  const torch::Tensor exact = reference.to(torch::kDouble);
  return (ours.to(torch::kDouble) - exact).abs().max().item<double>() /
         exact.abs().max().item<double>();
}

// Products oneDNN refused and the BLAS ran instead (preinit/gemm_onednn.cc); 0 without it.
int64_t RefusedProducts() {
  auto refused = reinterpret_cast<int64_t (*)()>(dlsym(RTLD_DEFAULT, "manyworlds_gemm_refused"));
  return refused != nullptr ? refused() : 0;
}

torch::Tensor Random(std::vector<int64_t> shape, uint64_t seed) {
  at::Generator generator = at::detail::createCPUGenerator(seed);
  return torch::randn(shape, generator);
}

TEST(GemmTest, ProductsRunOnOneDnnWhereTheProcessHasIt) {
  const bool has_onednn = dlsym(RTLD_DEFAULT, "dnnl_sgemm") != nullptr;
  const char* choice = std::getenv("MANYWORLDS_GEMM");
  const bool chosen = choice == nullptr || std::string(choice) != "openblas";
  EXPECT_EQ(CurrentThreads().gemm, has_onednn && chosen ? "onednn" : "blas");
}

// oneDNN takes every product (a refused one falls back to the BLAS, right but slow)
TEST(GemmTest, EveryTransposeAndStrideGivesTheProduct) {
  const int64_t refused_before = RefusedProducts();
  const torch::Tensor a = Random({70, 45}, 1), b = Random({45, 33}, 2);
  const torch::Tensor exact = a.to(torch::kDouble).mm(b.to(torch::kDouble));
  // the layouts libtorch passes as transposes: a^T stored, b^T stored, both
  const torch::Tensor a_t = a.t().contiguous().t(), b_t = b.t().contiguous().t();
  for (const auto& [x, y] : {std::pair{a, b}, {a_t, b}, {a, b_t}, {a_t, b_t}}) {
    EXPECT_LT(RelativeError(x.mm(y), exact), 1e-5);
  }
  // leading dimensions larger than the rows: slices of wider matrices
  const torch::Tensor wide_a = Random({70, 60}, 3).narrow(1, 5, 45);
  const torch::Tensor wide_b = Random({45, 50}, 4).narrow(1, 10, 33);
  EXPECT_LT(
      RelativeError(wide_a.mm(wide_b), wide_a.to(torch::kDouble).mm(wide_b.to(torch::kDouble))),
      1e-5);
  // Linear's three products: x W^T, g W, g^T x
  const torch::Tensor x = Random({128, 49}, 5), w = Random({400, 49}, 6), g = Random({128, 400}, 7);
  EXPECT_LT(RelativeError(torch::linear(x, w), x.to(torch::kDouble).mm(w.to(torch::kDouble).t())),
            1e-5);
  EXPECT_LT(RelativeError(g.mm(w), g.to(torch::kDouble).mm(w.to(torch::kDouble))), 1e-5);
  EXPECT_LT(RelativeError(g.t().mm(x), g.to(torch::kDouble).t().mm(x.to(torch::kDouble))), 1e-5);
  EXPECT_EQ(RefusedProducts(), refused_before);
}

TEST(GemmTest, AccumulationAndUninitialisedOutputsFollowBlas) {
  const torch::Tensor a = Random({64, 32}, 8), b = Random({32, 48}, 9), c = Random({64, 48}, 10);
  // beta 1, alpha 0.5: addmm
  const torch::Tensor exact =
      c.to(torch::kDouble) + 0.5 * a.to(torch::kDouble).mm(b.to(torch::kDouble));
  EXPECT_LT(RelativeError(torch::addmm(c, a, b, /*beta=*/1.0, /*alpha=*/0.5), exact), 1e-5);
  // beta 0 must not read the output: NaN there stays out of the product
  torch::Tensor out = torch::full({64, 48}, std::nan(""));
  torch::mm_out(out, a, b);
  EXPECT_FALSE(out.isnan().any().item<bool>());
  EXPECT_LT(RelativeError(out, a.to(torch::kDouble).mm(b.to(torch::kDouble))), 1e-5);
  // batched products (the twin critics' baddbmm)
  const torch::Tensor p = Random({2, 40, 30}, 11), q = Random({2, 30, 20}, 12);
  EXPECT_LT(RelativeError(torch::bmm(p, q), p.to(torch::kDouble).bmm(q.to(torch::kDouble))), 1e-5);
  // empty inner dimension: C = beta C
  const torch::Tensor none = torch::addmm(c, torch::zeros({64, 0}), torch::zeros({0, 48}));
  EXPECT_TRUE(torch::equal(none, c));
}

TEST(GemmTest, AProductRepeatsBitForBit) {
  const torch::Tensor a = Random({300, 400}, 13), b = Random({400, 400}, 14);
  const torch::Tensor first = a.mm(b);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(torch::equal(a.mm(b), first));
}

}  // namespace
}  // namespace manyworlds::nn
