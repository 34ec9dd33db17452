// Single-precision matrix products at the sizes of a SAC update (batch 128,
// 3 x 400 networks), through libtorch and the BLAS it runs on. These are the
// ceiling for `manyworlds bench agent`: an update is ~1.37 GFLOP, almost all
// of it in products like these (docs/benchmarks.md, "SAC updates").
//
//   BM_Product/M/K/N/T      (M x K) @ (K x N), BLAS at T threads
//   BM_TwoProductsAtOnce/M/K/N  two such products at the same time on two
//                           threads, BLAS at one thread each: what two cores
//                           give when each works on its own product
// Counter GFLOP/s: 2 M K N per product.

#include <thread>

#include <benchmark/benchmark.h>
#include <torch/torch.h>

#include "manyworlds/nn/threads.h"

namespace manyworlds {
namespace {

double ProductFlops(const benchmark::State& state) {
  return 2.0 * static_cast<double>(state.range(0)) * static_cast<double>(state.range(1)) *
         static_cast<double>(state.range(2));
}

void BM_Product(benchmark::State& state) {
  nn::SetThreads(1, static_cast<int>(state.range(3)));
  const torch::Tensor a = torch::randn({state.range(0), state.range(1)});
  const torch::Tensor b = torch::randn({state.range(1), state.range(2)});
  torch::Tensor c = torch::empty({state.range(0), state.range(2)});
  for (auto _ : state) {
    torch::mm_out(c, a, b);
    benchmark::DoNotOptimize(c.data_ptr<float>());
  }
  state.counters["GFLOP/s"] = benchmark::Counter(ProductFlops(state) * 1e-9,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}

void BM_TwoProductsAtOnce(benchmark::State& state) {
  nn::SetThreads(1, 1);
  const torch::Tensor a = torch::randn({state.range(0), state.range(1)});
  const torch::Tensor b = torch::randn({state.range(1), state.range(2)});
  torch::Tensor c0 = torch::empty({state.range(0), state.range(2)});
  torch::Tensor c1 = torch::empty({state.range(0), state.range(2)});
  constexpr int kProductsPerThread = 50;
  for (auto _ : state) {
    std::thread other([&] {
      for (int i = 0; i < kProductsPerThread; ++i) torch::mm_out(c1, a, b);
    });
    for (int i = 0; i < kProductsPerThread; ++i) torch::mm_out(c0, a, b);
    other.join();
  }
  state.counters["GFLOP/s"] = benchmark::Counter(
      2 * kProductsPerThread * ProductFlops(state) * 1e-9,
      benchmark::Counter::kIsIterationInvariantRate);
}

// Hidden layer forward (128x400x400), weight gradient (400x128x400), first
// layer (128x43x400); and a large product for the machine's peak.
void ProductSizes(benchmark::internal::Benchmark* b) {
  for (int threads : {1, 2}) {
    b->Args({128, 400, 400, threads});
    b->Args({400, 128, 400, threads});
    b->Args({128, 43, 400, threads});
    b->Args({1024, 1024, 1024, threads});
  }
}
BENCHMARK(BM_Product)->Apply(ProductSizes)->UseRealTime();
BENCHMARK(BM_TwoProductsAtOnce)
    ->Args({128, 400, 400})
    ->Args({400, 128, 400})
    ->Args({1024, 1024, 1024})
    ->UseRealTime();

}  // namespace
}  // namespace manyworlds

BENCHMARK_MAIN();
