// A small fixed set of threads that runs the parts of one computation at once:
// Run(n, fn) calls fn(0) ... fn(n-1), the calling thread taking part, and
// returns when all are done. Learners use it to split an update's batch
// (data-parallel shards with single-threaded BLAS in each) instead of
// splitting every small matrix product across cores, which scales poorly at
// SAC sizes (nn/threads.h).
//
// Which thread runs which part is not fixed, so fn must make results depend
// on the part index only. The first exception thrown by a part is rethrown
// by Run after every part has finished. Workers start with libtorch's
// intra-op thread count (at::init_num_threads), so a one-thread setting holds
// in them too. Run is not reentrant and not thread-safe.
#ifndef MANYWORLDS_NN_WORKER_POOL_H_
#define MANYWORLDS_NN_WORKER_POOL_H_

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace manyworlds::nn {

class WorkerPool {
 public:
  // num_threads counts the caller: 1 runs everything inline, no thread.
  // Throws ConfigError if num_threads < 1.
  explicit WorkerPool(int num_threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  void Run(int num_parts, const std::function<void(int)>& fn);
  int num_threads() const { return static_cast<int>(workers_.size()) + 1; }

 private:
  void WorkerLoop();
  // Claims and runs parts of the current job until none is left.
  void Drain();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable work_done_;
  const std::function<void(int)>* job_ = nullptr;
  int num_parts_ = 0;
  int next_part_ = 0;
  int parts_done_ = 0;
  uint64_t generation_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
};

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_WORKER_POOL_H_
