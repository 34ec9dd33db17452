// The bounds on counts that every entry point checks against: the CLI's options, the training
// config, the Python package and the executor itself read them from here, so that one number
// says how many threads or envs manyworlds accepts. Sizes beyond them are refused with a
// ConfigError before anything is allocated; sizes within them are still checked against this
// machine's memory (core/memory.h).
#ifndef MANYWORLDS_CORE_LIMITS_H_
#define MANYWORLDS_CORE_LIMITS_H_

#include <cstdint>
#include <exception>
#include <string>

namespace manyworlds {

// Worker threads of one executor, rollout or trainer: more than any machine we run on has
// cores, and few enough that a typo (10^9) is an error instead of an abort when the system
// refuses the threads.
inline constexpr int kMaxThreads = 256;

// Envs stepped together by one executor or vector env (the CLI's --num-envs, Python's
// make_vec): MT50 at 1,000 envs per task fits; 10^8 is a typo.
inline constexpr int64_t kMaxEnvs = 65536;

// The error for a thread the system would not start (ulimit -u or -v, no memory), thrown by the
// code that asked for `wanted` threads with `setting` after joining those it started:
// "cannot start thread 5 of 300 (<reason>); lower <setting>".
[[noreturn]] void ThrowThreadsNotStarted(const std::exception& cause, int64_t started,
                                         int64_t wanted, const std::string& setting);

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_LIMITS_H_
