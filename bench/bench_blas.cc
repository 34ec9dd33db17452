// Which single-precision GEMM library is fastest at the shapes of our learners' updates, one
// thread each, in one run. The libraries are the Debian packages libtorch could run on:
//   openblas  libopenblas0-pthread (what Debian's libtorch calls through libblas.so.3)
//   blis      libblis4-pthread     (apt-get install libblis4-pthread)
//   onednn    libdnnl2             (linked by Debian's libtorch; dnnl_sgemm)
// Each is loaded with dlopen (RTLD_LOCAL: OpenBLAS and BLIS export the same symbols) and set to
// one thread; a library that is not installed is reported as skipped. libxsmm is left out: it
// generates kernels for products up to (M N K)^(1/3) of about 128 and hands larger ones back to
// BLAS (its Q&A), and a SAC layer at batch 128 is already (128 x 400 x 400)^(1/3) = 294.
//
//   BM_Mlp/<library>/<batch>      every product of one forward and backward pass of a 3 x 400 MLP
//                                 (inputs 49: MT10's 39 observations and a one-hot of 10 tasks;
//                                 outputs 8), in the order an update runs them; the first layer
//                                 has no input gradient
//   BM_Product/<library>/<name>   one product of a 400 x 400 layer at batch 1,280: forward
//                                 (x W^T), input gradient (g W), weight gradient (g^T x)
// Counter GFLOP/s: 2 M K N per product. Run with --benchmark_enable_random_interleaving=true
// and repetitions so that the libraries alternate on a noisy machine (docs/benchmarks.md).
#include <benchmark/benchmark.h>
#include <dlfcn.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace {

// C (M x N) = op(A) op(B), row-major, alpha 1, beta 0.
using Sgemm = void (*)(bool trans_a, bool trans_b, int64_t m, int64_t n, int64_t k, const float* a,
                       const float* b, float* c);

struct Library {
  std::string name;
  Sgemm sgemm = nullptr;
  std::string missing;  // why it could not be loaded
};

// cblas_sgemm's signature (CBLAS enums as ints: row-major 101, no-trans 111, trans 112).
using CblasSgemm = void (*)(int, int, int, int, int, int, float, const float*, int, const float*,
                            int, float, float*, int);
using DnnlSgemm = int (*)(char, char, int64_t, int64_t, int64_t, float, const float*, int64_t,
                          const float*, int64_t, float, float*, int64_t);

CblasSgemm openblas_sgemm = nullptr;
CblasSgemm blis_sgemm = nullptr;
DnnlSgemm dnnl_sgemm = nullptr;

template <CblasSgemm* fn>
void CallCblas(bool ta, bool tb, int64_t m, int64_t n, int64_t k, const float* a, const float* b,
               float* c) {
  (*fn)(101, ta ? 112 : 111, tb ? 112 : 111, static_cast<int>(m), static_cast<int>(n),
        static_cast<int>(k), 1.0f, a, static_cast<int>(ta ? m : k), b, static_cast<int>(tb ? k : n),
        0.0f, c, static_cast<int>(n));
}

void CallDnnl(bool ta, bool tb, int64_t m, int64_t n, int64_t k, const float* a, const float* b,
              float* c) {
  dnnl_sgemm(ta ? 'T' : 'N', tb ? 'T' : 'N', m, n, k, 1.0f, a, ta ? m : k, b, tb ? k : n, 0.0f, c,
             n);
}

void* Open(const std::vector<std::string>& paths, std::string& missing) {
  for (const std::string& path : paths) {
    if (void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND)) return handle;
  }
  missing = "not installed (" + paths.front() + ")";
  return nullptr;
}

std::vector<Library> LoadLibraries() {
  std::vector<Library> libraries;
  const std::string lib = "/usr/lib/x86_64-linux-gnu/";
  {
    Library l{"openblas", nullptr, ""};
    if (void* h = Open({lib + "libopenblas.so.0", "libopenblas.so.0"}, l.missing)) {
      openblas_sgemm = reinterpret_cast<CblasSgemm>(dlsym(h, "cblas_sgemm"));
      if (auto threads = reinterpret_cast<void (*)(int)>(dlsym(h, "openblas_set_num_threads"))) {
        threads(1);
      }
      if (openblas_sgemm != nullptr) l.sgemm = &CallCblas<&openblas_sgemm>;
    }
    libraries.push_back(l);
  }
  {
    Library l{"blis", nullptr, ""};
    if (void* h = Open(
            {lib + "blis-pthread/libblis.so.4", lib + "blis-openmp/libblis.so.4", "libblis.so.4"},
            l.missing)) {
      blis_sgemm = reinterpret_cast<CblasSgemm>(dlsym(h, "cblas_sgemm"));
      if (auto threads =
              reinterpret_cast<void (*)(int64_t)>(dlsym(h, "bli_thread_set_num_threads"))) {
        threads(1);
      }
      if (blis_sgemm != nullptr) l.sgemm = &CallCblas<&blis_sgemm>;
    }
    libraries.push_back(l);
  }
  {
    Library l{"onednn", nullptr, ""};
    if (void* h = Open({lib + "libdnnl.so.2", "libdnnl.so.2"}, l.missing)) {
      dnnl_sgemm = reinterpret_cast<DnnlSgemm>(dlsym(h, "dnnl_sgemm"));
      if (dnnl_sgemm != nullptr) l.sgemm = &CallDnnl;
    }
    libraries.push_back(l);
  }
  return libraries;
}

struct Product {
  bool trans_a, trans_b;
  int64_t m, n, k;
};

// The products of one forward and backward pass of a Linear layer in -> out at batch b:
// forward x (b, in) W^T, input gradient g (b, out) W (out, in), weight gradient g^T x.
void LayerProducts(int64_t b, int64_t in, int64_t out, bool input_gradient,
                   std::vector<Product>& products) {
  products.push_back({false, true, b, out, in});
  if (input_gradient) products.push_back({false, false, b, in, out});
  products.push_back({true, false, out, in, b});
}

std::vector<float> Random(int64_t size, uint32_t seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::vector<float> v(static_cast<size_t>(size));
  for (float& x : v) x = uniform(generator);
  return v;
}

void Run(benchmark::State& state, const Library& library, const std::vector<Product>& products) {
  if (library.sgemm == nullptr) {
    state.SkipWithError((library.name + ": " + library.missing).c_str());
    return;
  }
  std::vector<std::vector<float>> a, b, c;
  double flops = 0.0;
  for (size_t i = 0; i < products.size(); ++i) {
    const Product& p = products[i];
    a.push_back(Random(p.m * p.k, static_cast<uint32_t>(2 * i + 1)));
    b.push_back(Random(p.k * p.n, static_cast<uint32_t>(2 * i + 2)));
    c.emplace_back(static_cast<size_t>(p.m * p.n));
    flops += 2.0 * static_cast<double>(p.m) * static_cast<double>(p.n) * static_cast<double>(p.k);
  }
  for (auto _ : state) {
    for (size_t i = 0; i < products.size(); ++i) {
      const Product& p = products[i];
      library.sgemm(p.trans_a, p.trans_b, p.m, p.n, p.k, a[i].data(), b[i].data(), c[i].data());
    }
    benchmark::DoNotOptimize(c.back().data());
    benchmark::ClobberMemory();
  }
  state.counters["GFLOP/s"] =
      benchmark::Counter(flops * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

int main(int argc, char** argv) {
  setenv("OMP_NUM_THREADS", "1", /*overwrite=*/1);  // oneDNN's OpenMP, read when it loads
  static const std::vector<Library> libraries = LoadLibraries();
  const std::vector<int64_t> widths = {49, 400, 400, 400, 8};
  for (const Library& library : libraries) {
    for (const int64_t batch : {128, 320, 1280}) {
      std::vector<Product> products;
      for (size_t i = 0; i + 1 < widths.size(); ++i) {
        LayerProducts(batch, widths[i], widths[i + 1], /*input_gradient=*/i > 0, products);
      }
      benchmark::RegisterBenchmark(
          ("BM_Mlp/" + library.name + "/" + std::to_string(batch)).c_str(),
          [&library, products](benchmark::State& state) { Run(state, library, products); });
    }
    std::vector<Product> layer;
    LayerProducts(1280, 400, 400, true, layer);
    const char* names[] = {"forward", "input_gradient", "weight_gradient"};
    for (size_t i = 0; i < layer.size(); ++i) {
      benchmark::RegisterBenchmark(("BM_Product/" + library.name + "/" + names[i]).c_str(),
                                   [&library, product = layer[i]](benchmark::State& state) {
                                     Run(state, library, {product});
                                   });
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
