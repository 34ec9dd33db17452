// An exclusive lock on a run directory, held while a Trainer writes it, so
// two `manyworlds train` processes can never write the same run (an advisory
// flock on RUN_DIR/.lock: released by the kernel when the process ends, even
// by kill -9, so a stale lock never locks the user out).
#ifndef MANYWORLDS_EXPERIMENTS_RUN_RUN_LOCK_H_
#define MANYWORLDS_EXPERIMENTS_RUN_RUN_LOCK_H_

#include <filesystem>

namespace manyworlds::experiments {

class RunLock {
 public:
  // Takes the lock on an existing directory without waiting. Throws
  // ConfigError naming the process that holds it, or Error if the lock file
  // cannot be created.
  explicit RunLock(const std::filesystem::path& run_dir);
  ~RunLock();
  RunLock(RunLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  RunLock& operator=(RunLock&&) = delete;
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_RUN_RUN_LOCK_H_
