#include "manyworlds/sim/mujoco_error.h"

#include <atomic>
#include <mutex>

#include <mujoco/mujoco.h>

namespace manyworlds::sim {
namespace {

thread_local std::string last_warning;
std::atomic<long> warning_count{0};

// Never returns: MuJoCo must not continue after mju_error.
[[noreturn]] void ThrowingErrorHandler(const char* message) {
  throw MujocoError(std::string("MuJoCo error: ") + (message ? message : "(no message)"));
}

void RecordingWarningHandler(const char* message) {
  last_warning = message ? message : "";
  warning_count.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

void InstallMujocoHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = &ThrowingErrorHandler;
    mju_user_warning = &RecordingWarningHandler;
  });
}

const std::string& LastMujocoWarning() { return last_warning; }

long MujocoWarningCount() { return warning_count.load(std::memory_order_relaxed); }

}  // namespace manyworlds::sim
