#include "manyworlds/nn/worker_pool.h"

#include <string>

#include <ATen/Parallel.h>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {

WorkerPool::WorkerPool(int num_threads) {
  if (num_threads < 1) {
    throw ConfigError("WorkerPool: num_threads must be >= 1, got " + std::to_string(num_threads));
  }
  for (int i = 1; i < num_threads; ++i) workers_.emplace_back([this] { WorkerLoop(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_ready_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void WorkerPool::Drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (job_ != nullptr && next_part_ < num_parts_) {
    const int part = next_part_++;
    const std::function<void(int)>& fn = *job_;
    lock.unlock();
    std::exception_ptr error;
    try {
      fn(part);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    if (error && !error_) error_ = error;
    if (++parts_done_ == num_parts_) work_done_.notify_all();
  }
}

void WorkerPool::WorkerLoop() {
  at::init_num_threads();
  uint64_t seen = 0;
  while (true) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_ready_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    Drain();
  }
}

void WorkerPool::Run(int num_parts, const std::function<void(int)>& fn) {
  if (num_parts <= 0) return;
  if (workers_.empty() || num_parts == 1) {
    for (int i = 0; i < num_parts; ++i) fn(i);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &fn;
    num_parts_ = num_parts;
    next_part_ = 0;
    parts_done_ = 0;
    error_ = nullptr;
    ++generation_;
  }
  work_ready_.notify_all();
  Drain();
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    work_done_.wait(lock, [&] { return parts_done_ == num_parts_; });
    job_ = nullptr;
    error = error_;
    error_ = nullptr;
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace manyworlds::nn
