// Does a product's rounding depend on how many threads oneDNN splits it over? Runs dnnl_sgemm,
// the library our programs' products go to (src/manyworlds/nn/preinit/gemm_onednn.cc), on the
// learners' weight-gradient shapes (X^T dY: M x N outputs, K batch rows) with 1, 2, 4, 8 and 16
// OpenMP threads, and prints a hash of each result: equal hashes, identical bits.
//
//   g++ -O2 -fopenmp bench/gemm_thread_rounding.cc -o /tmp/gemm_thread_rounding -l:libdnnl.so.2
//   /tmp/gemm_thread_rounding
//
// More threads than cores are fine here: the split, not the speed, decides the rounding.
#include <omp.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

extern "C" int dnnl_sgemm(char transa, char transb, int64_t m, int64_t n, int64_t k, float alpha,
                          const float* a, int64_t lda, const float* b, int64_t ldb, float beta,
                          float* c, int64_t ldc);

namespace {

uint32_t Fnv1a(const std::vector<float>& values) {
  uint32_t hash = 2166136261u;
  const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
  for (size_t i = 0; i < values.size() * sizeof(float); ++i) hash = (hash ^ bytes[i]) * 16777619u;
  return hash;
}

}  // namespace

int main() {
  struct Shape {
    int64_t m, n, k;
    const char* what;
  };
  const Shape shapes[] = {{39, 256, 1000, "PPO first layer, minibatch 1000"},
                          {256, 256, 1000, "PPO hidden layer"},
                          {49, 400, 320, "MT-SAC first layer, batch 320"},
                          {400, 400, 320, "MT-SAC hidden layer"},
                          {400, 400, 1280, "MT-SAC hidden layer, batch 1280"},
                          {10, 400, 6400, "a 10-wide input, batch 6400"}};
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> uniform(-0.5f, 0.5f);
  int differing = 0;
  for (const Shape& s : shapes) {
    std::vector<float> a(s.k * s.m), b(s.k * s.n), c(s.m * s.n);
    for (float& x : a) x = uniform(rng);
    for (float& x : b) x = uniform(rng);
    std::printf("%4ld x %4ld x %5ld  %-34s", static_cast<long>(s.m), static_cast<long>(s.n),
                static_cast<long>(s.k), s.what);
    uint32_t first = 0;
    bool same = true;
    for (int threads : {1, 2, 4, 8, 16}) {
      omp_set_num_threads(threads);
      std::memset(c.data(), 0, c.size() * sizeof(float));
      dnnl_sgemm('T', 'N', s.m, s.n, s.k, 1.0f, a.data(), s.m, b.data(), s.n, 0.0f, c.data(), s.n);
      const uint32_t hash = Fnv1a(c);
      if (threads == 1) first = hash;
      same = same && hash == first;
      std::printf("  %2d: %08x", threads, hash);
    }
    std::printf("  %s\n", same ? "same" : "DIFFERS");
    differing += same ? 0 : 1;
  }
  std::printf("%d of %zu shapes round differently on some thread count\n", differing,
              sizeof(shapes) / sizeof(shapes[0]));
  return 0;
}
