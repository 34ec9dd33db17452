#include "manyworlds/nn/threads.h"

#include <dlfcn.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <string>

#include <torch/torch.h>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {
namespace {

std::atomic<bool> explicitly_set{false};

// OpenBLAS's C entry points, looked up at run time: libtorch reaches BLAS
// through libblas.so.3, which may be OpenBLAS or another implementation.
template <typename Fn>
Fn FindBlasFunction(const char* name) {
  return reinterpret_cast<Fn>(dlsym(RTLD_DEFAULT, name));
}

}  // namespace

void ConfigureTorchThreads(bool own_threads) {
  if (explicitly_set.load()) return;
  if (torch::get_num_threads() != 1) torch::set_num_threads(1);
  if (own_threads) {
    if (auto set = FindBlasFunction<void (*)(int)>("openblas_set_num_threads")) set(1);
  }
}

void SetThreads(int torch_threads, int blas_threads) {
  if (torch_threads < 1 || blas_threads < 0) {
    throw ConfigError("threads: torch threads must be >= 1 and BLAS threads >= 0 (0 = leave), " +
                      std::string("got ") + std::to_string(torch_threads) + " and " +
                      std::to_string(blas_threads));
  }
  if (torch_threads > 1 && blas_threads > 1) {
    throw ConfigError("threads: torch intra-op threads (" + std::to_string(torch_threads) +
                      ") and BLAS threads (" + std::to_string(blas_threads) +
                      ") may not both be > 1: nested pools oversubscribe the CPU");
  }
  if (blas_threads > 0) {
    auto set = FindBlasFunction<void (*)(int)>("openblas_set_num_threads");
    if (set == nullptr) {
      throw ConfigError("threads: the BLAS library is not OpenBLAS; cannot set its threads");
    }
    set(blas_threads);
  }
  torch::set_num_threads(torch_threads);
  explicitly_set.store(true);
}

ThreadInfo CurrentThreads() {
  ThreadInfo info;
  info.torch_intra_op = torch::get_num_threads();
  info.torch_inter_op = torch::get_num_interop_threads();
  if (auto get = FindBlasFunction<int (*)()>("openblas_get_num_threads")) {
    info.blas_threads = get();
  }
  auto config = FindBlasFunction<char* (*)()>("openblas_get_config");
  info.blas = config != nullptr ? std::string(config()) : "unknown";
  auto core = FindBlasFunction<char* (*)()>("openblas_get_corename");
  info.blas_core = core != nullptr ? std::string(core()) : "unknown";
  auto gemm = FindBlasFunction<const char* (*)()>("manyworlds_gemm_library");
  info.gemm = gemm != nullptr ? std::string(gemm()) : "blas";
  return info;
}

std::string BlasContentionAdvice(double load_average, int blas_threads) {
  if (blas_threads <= 1 || load_average < 0.75) return "";
  char load[32];
  std::snprintf(load, sizeof(load), "%.2f", load_average);
  return "other processes keep the cores busy (load average " + std::string(load) +
         ") and the products run " + std::to_string(blas_threads) +
         " threads: beside other work the updates run up to 28x slower. Start runs that share "
         "the machine with OPENBLAS_NUM_THREADS=1, or keep the threads with "
         "OMP_WAIT_POLICY=passive (docs/benchmarks.md, \"BLAS threads on a shared machine\")";
}

double OneMinuteLoadAverage() {
  std::ifstream in("/proc/loadavg");
  double load = -1.0;
  if (!(in >> load)) return -1.0;
  return load;
}

}  // namespace manyworlds::nn
