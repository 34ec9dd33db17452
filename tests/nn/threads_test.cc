#include "manyworlds/nn/threads.h"

#include <string>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {
namespace {

TEST(BlasKernelsTest, OpenBlasRunsTheKernelsOfThisCpu) {
  // Without preinit/blas_coretype.cc, Debian's OpenBLAS runs its generic
  // SSE3 "Prescott" kernels on CPUs newer than it knows.
  const ThreadInfo info = CurrentThreads();
  if (info.blas_core == "unknown") GTEST_SKIP() << "the BLAS library is not OpenBLAS";
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    for (const char* generic : {"Prescott", "Core2", "Penryn", "Dunnington", "Nehalem",
                                "Sandybridge", "Katmai", "Atom"}) {
      EXPECT_NE(info.blas_core, generic) << "AVX2 CPU running generic kernels";
    }
  }
}

TEST(ThreadsTest, LearnerDefaultIsOneIntraOpThreadAndBlasOneWithOwnThreads) {
  ConfigureTorchThreads(/*own_threads=*/true);
  const ThreadInfo info = CurrentThreads();
  EXPECT_EQ(info.torch_intra_op, 1);
  if (info.blas_threads >= 0) {
    EXPECT_EQ(info.blas_threads, 1);
  }
  EXPECT_THROW(SetThreads(2, 2), ConfigError);
  EXPECT_THROW(SetThreads(0, 1), ConfigError);
}

// The advice names the load and the remedy, and only when both apply.
TEST(ThreadsTest, BlasContentionAdviceOnlyForSeveralThreadsOnABusyMachine) {
  const std::string advice = BlasContentionAdvice(1.8, 2);
  EXPECT_NE(advice.find("load average 1.80"), std::string::npos) << advice;
  EXPECT_NE(advice.find("OPENBLAS_NUM_THREADS=1"), std::string::npos) << advice;
  EXPECT_NE(advice.find("OMP_WAIT_POLICY=passive"), std::string::npos) << advice;
  EXPECT_EQ(BlasContentionAdvice(1.8, 1), "");
  EXPECT_EQ(BlasContentionAdvice(0.2, 2), "");
  EXPECT_EQ(BlasContentionAdvice(-1.0, 2), "");  // unreadable load average
  EXPECT_GE(OneMinuteLoadAverage(), 0.0);        // Linux has /proc/loadavg
}

// The kernels selected at start-up compute correct products (against a
// double-precision loop), on one BLAS thread and on several. Last, in a
// suite of its own so that it runs after the others in one process:
// SetThreads is process-wide and final (ConfigureTorchThreads then leaves
// the threads alone), and ThreadsTest needs the defaults.
TEST(BlasProductsTest, SelectedKernelsMultiplyCorrectly) {
  // PyPI's libtorch multiplies with the MKL inside it, whose threads follow torch's
  if (CurrentThreads().blas == "unknown") GTEST_SKIP() << "the BLAS library is not OpenBLAS";
  torch::manual_seed(3);
  const torch::Tensor a = torch::randn({128, 43});
  const torch::Tensor b = torch::randn({43, 400});
  torch::Tensor expected = torch::zeros({128, 400}, torch::kFloat64);
  auto x = a.accessor<float, 2>();
  auto y = b.accessor<float, 2>();
  auto z = expected.accessor<double, 2>();
  for (int64_t i = 0; i < 128; ++i) {
    for (int64_t k = 0; k < 43; ++k) {
      for (int64_t j = 0; j < 400; ++j) z[i][j] += static_cast<double>(x[i][k]) * y[k][j];
    }
  }
  for (int threads : {1, 2}) {
    SetThreads(1, threads);
    const torch::Tensor product = torch::mm(a, b).to(torch::kFloat64);
    EXPECT_LT((product - expected).abs().max().item<double>(), 1e-4) << threads << " threads";
  }
}

}  // namespace
}  // namespace manyworlds::nn
