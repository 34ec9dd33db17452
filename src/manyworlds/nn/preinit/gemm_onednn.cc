// Runs libtorch's single-precision matrix products on oneDNN's sgemm instead of OpenBLAS's.
//
// Debian's libtorch computes every float product of a CPU learner (Linear layers, the twin
// critics' batched products, convolutions through im2col) with the Fortran BLAS call sgemm_,
// which libblas.so.3 resolves to OpenBLAS. Measured one thread each on this project's shapes
// (bench/bench_blas.cc; docs/benchmarks.md, "Which GEMM library"), oneDNN's dnnl_sgemm is the
// faster of the GEMM libraries Debian has (OpenBLAS, BLIS, oneDNN), and libtorch already loads
// oneDNN. This file defines sgemm_ in the executable, which the dynamic linker then binds
// libtorch's calls to ahead of libblas.so.3 (an executable's symbols come first), and forwards
// each product to dnnl_sgemm with as many OpenMP threads as OpenBLAS is set to
// (openblas_set_num_threads stays the one thread setting; nn/threads.h).
//
// MANYWORLDS_GEMM=openblas, read once, hands every call to the BLAS library instead; so does a
// process without dnnl_sgemm (a libtorch that links oneDNN privately, as PyPI's wheels do, never
// calls this sgemm_ at all). Products with an empty dimension or arguments oneDNN refuses go to
// the BLAS library too, which reports them as BLAS does. The nn layer links this file into every
// executable built in this project that links it, like blas_coretype.cc.
#include <dlfcn.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace {

using FortranSgemm = void (*)(const char*, const char*, const int*, const int*, const int*,
                              const float*, const float*, const int*, const float*, const int*,
                              const float*, float*, const int*);
using DnnlSgemm = int (*)(char, char, int64_t, int64_t, int64_t, float, const float*, int64_t,
                          const float*, int64_t, float, float*, int64_t);

struct Gemm {
  FortranSgemm blas = nullptr;  // the next sgemm_ in load order: libblas.so.3's
  DnnlSgemm onednn = nullptr;   // null: every product goes to blas
  int (*blas_threads)() = nullptr;
  int (*omp_max_threads)() = nullptr;
  void (*omp_set_threads)(int) = nullptr;
};

// The symbol from the global scope or, failing that, from `library` if the process has already
// loaded it privately: Python loads libtorch and its libraries with RTLD_LOCAL, so this file
// preloaded into a Python peer (LD_PRELOAD, docs/benchmarks.md) finds them only this way. Never
// loads a library.
void* Find(const char* symbol, const char* library, void* scope = RTLD_DEFAULT) {
  if (void* found = dlsym(scope, symbol)) return found;
  void* handle = dlopen(library, RTLD_NOW | RTLD_NOLOAD);
  return handle != nullptr ? dlsym(handle, symbol) : nullptr;
}

const Gemm& Resolve() {
  static const Gemm gemm = [] {
    Gemm g;
    g.blas = reinterpret_cast<FortranSgemm>(Find("sgemm_", "libblas.so.3", RTLD_NEXT));
    const char* choice = std::getenv("MANYWORLDS_GEMM");
    if (choice == nullptr || std::strcmp(choice, "openblas") != 0) {
      g.onednn = reinterpret_cast<DnnlSgemm>(Find("dnnl_sgemm", "libdnnl.so.2"));
      g.blas_threads =
          reinterpret_cast<int (*)()>(Find("openblas_get_num_threads", "libblas.so.3"));
      g.omp_max_threads = reinterpret_cast<int (*)()>(Find("omp_get_max_threads", "libgomp.so.1"));
      g.omp_set_threads =
          reinterpret_cast<void (*)(int)>(Find("omp_set_num_threads", "libgomp.so.1"));
      if (g.omp_max_threads == nullptr || g.omp_set_threads == nullptr) g.onednn = nullptr;
    }
    return g;
  }();
  return gemm;
}

// Products with every dimension > 0 that went to the BLAS because oneDNN refused them: none is
// expected (tests/nn/gemm_test.cc checks); each would run at OpenBLAS's speed.
std::atomic<int64_t> refused_products{0};

}  // namespace

extern "C" {

// Fortran BLAS sgemm (column-major): C = alpha op(A) op(B) + beta C, C m x n. A column-major
// matrix is its transpose row-major, so the row-major dnnl_sgemm computes C^T = op(B)^T op(A)^T
// with the operands swapped.
void sgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const float* alpha, const float* a, const int* lda, const float* b, const int* ldb,
            const float* beta, float* c, const int* ldc) {
  const Gemm& gemm = Resolve();
  if (gemm.onednn != nullptr && *m > 0 && *n > 0 && *k > 0) {
    const int saved = gemm.omp_max_threads();
    const int threads = gemm.blas_threads != nullptr ? gemm.blas_threads() : saved;
    if (threads != saved) gemm.omp_set_threads(threads);
    const int status =
        gemm.onednn(*transb, *transa, *n, *m, *k, *alpha, b, *ldb, a, *lda, *beta, c, *ldc);
    if (threads != saved) gemm.omp_set_threads(saved);
    if (status == 0) return;  // dnnl_success
    refused_products.fetch_add(1, std::memory_order_relaxed);
  }
  if (gemm.blas == nullptr) std::abort();  // no BLAS behind us: libtorch cannot run at all
  gemm.blas(transa, transb, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc);
}

// "onednn" when products go to dnnl_sgemm, else "blas" (read by nn::CurrentThreads).
const char* manyworlds_gemm_library() { return Resolve().onednn != nullptr ? "onednn" : "blas"; }

// How many products oneDNN refused so far (see refused_products).
int64_t manyworlds_gemm_refused() { return refused_products.load(std::memory_order_relaxed); }

}  // extern "C"
