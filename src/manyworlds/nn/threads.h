// Thread configuration for libtorch on small CPU machines.
//
// Two thread pools can parallelise a network update: libtorch's intra-op
// pool (OpenMP; elementwise ops, reductions, and GEMMs when libtorch does
// them itself) and the BLAS library's own pool (OpenBLAS-pthread on Debian,
// sized by OPENBLAS_NUM_THREADS, default one thread per core), which runs
// every GEMM. Nested, they oversubscribe the CPU: on 2 cores a SAC update
// took 84 ms with OpenMP 2 + OpenBLAS 2 against 16.5 ms with OpenMP 1 +
// OpenBLAS 2 (our measurement, libtorch 1.13.1 and OpenBLAS 0.3.21 on 2
// cores). So at most one of them may be > 1.
//
// Measured with `manyworlds bench agent` on the 2-core build machine (AMD
// EPYC, libtorch 1.13.1, OpenBLAS 0.3.21 pthread "Haswell" kernels; SAC
// update, batch 128, 3 x 400, obs 39, action 4, one task; median of 5 x 20
// updates, 2-4 interleaved rounds; the machine was shared, +-15%):
//   torch 1, BLAS 2 (the default)        70.7 - 74.0 updates/s  (13.8 ms)
//   torch 1, BLAS 2 set at run time      72.1 - 72.4
//   torch 2, BLAS 1                      55.6 - 58.8  (the intra-op pool
//                                        runs the two critics' baddbmm in
//                                        parallel, but GEMMs are 1-thread)
//   torch 1, BLAS 1 set at run time      58.9 - 61.5
//   torch 1, OPENBLAS_NUM_THREADS=1      35.8 - 37.0  (slower than setting 1
//                                        thread at run time; not explained)
//   torch 2, BLAS 2                      refused by SetThreads (84 ms, the
//                                        measurement above)
// Splitting every small product across cores is the weak point: one thread
// already runs the update at ~85 GFLOP/s (the sgemm rate of one core), two
// BLAS threads reach only ~100. Data-parallel updates (SacConfig
// update_shards, nn/worker_pool.h) instead run half the batch on each core
// with one-thread BLAS; see docs/benchmarks.md for the figures.
// The default (ConfigureTorchThreads) is therefore torch 1, with BLAS at one
// thread when the caller runs its own threads and left at its own default
// (one thread per core) otherwise.
// The products themselves run on oneDNN in this project's programs
// (preinit/gemm_onednn.cc) with OpenBLAS's thread count: "BLAS threads" below
// are the products' threads whichever library runs them. The figures above
// were measured on OpenBLAS.
#ifndef MANYWORLDS_NN_THREADS_H_
#define MANYWORLDS_NN_THREADS_H_

#include <string>

namespace manyworlds::nn {

// The default: libtorch's intra-op pool to one thread, GEMM parallelism left
// to the BLAS library's pool (OPENBLAS_NUM_THREADS, default one thread per
// core), or, with own_threads (the caller parallelises across its own
// threads), OpenBLAS set to one thread. Does nothing after SetThreads (an
// explicit choice wins). Idempotent and cheap; every learner calls it.
void ConfigureTorchThreads(bool own_threads = false);

// An explicit configuration: torch intra-op threads and, when the BLAS is
// OpenBLAS, its thread count (blas_threads 0 leaves the BLAS alone). Throws
// ConfigError if a count is negative, torch_threads is 0, or both are > 1
// (nested pools oversubscribe the CPU). Process-wide.
void SetThreads(int torch_threads, int blas_threads);

struct ThreadInfo {
  int torch_intra_op = 0;
  int torch_inter_op = 0;
  int blas_threads = -1;  // -1 when the BLAS library cannot say
  std::string blas;       // openblas_get_config(), or "unknown"
  std::string blas_core;  // openblas_get_corename() (the kernels in use), or "unknown"
  // What runs libtorch's float products: "onednn" (preinit/gemm_onednn.cc, this project's
  // programs) or "blas" (the BLAS library: MANYWORLDS_GEMM=openblas, or a program without it).
  std::string gemm;
};
ThreadInfo CurrentThreads();

// Advice for a run about to start with `blas_threads` OpenBLAS threads while
// the machine's one-minute load average is `load_average`: beside other busy
// processes, OpenBLAS workers on every core wait for each other's time
// slices and updates run 5-14x slower (docs/benchmarks.md, "BLAS threads on
// a shared machine"). Empty when there is nothing to say (one thread, or a
// load average below 0.75).
std::string BlasContentionAdvice(double load_average, int blas_threads);

// The one-minute load average (/proc/loadavg), or -1 where it cannot be read.
double OneMinuteLoadAverage();

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_THREADS_H_
