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

}  // namespace
}  // namespace manyworlds::nn
