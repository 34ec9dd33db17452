// Thread configuration for libtorch on small CPU machines.
#ifndef MANYWORLDS_NN_THREADS_H_
#define MANYWORLDS_NN_THREADS_H_

namespace manyworlds::nn {

// Sets libtorch's intra-op (OpenMP) pool to one thread and leaves GEMM
// parallelism to the BLAS library's own pool (OPENBLAS_NUM_THREADS, default
// one thread per core). Both layers default to one thread per core and, when
// nested, oversubscribe the CPU: on 2 cores a SAC update took 84 ms with
// OpenMP 2 + OpenBLAS 2 versus 16.5 ms with OpenMP 1 + OpenBLAS 2, the
// fastest setting measured (performance.md §5.2). Idempotent and cheap.
void ConfigureTorchThreads();

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_THREADS_H_
