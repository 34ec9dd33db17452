// An env checker in the spirit of Gymnasium's check_env, usable on any Env
// (ours or a user's). It needs a factory because several checks compare
// independent instances.
#ifndef MANYWORLDS_CORE_ENV_CHECKER_H_
#define MANYWORLDS_CORE_ENV_CHECKER_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/env.h"

namespace manyworlds {

struct CheckOptions {
  int64_t steps = 300;     // random-action steps per trajectory comparison
  uint64_t seed = 1;       // env seed used by the checks
  uint64_t task_seed = 2;  // task seed used by the checks
};

struct CheckResult {
  std::string name;     // e.g. "same-seeds-identical-trajectories"
  bool passed = false;
  std::string message;  // what failed, or a short note
};

struct CheckReport {
  std::string env_id;
  std::vector<CheckResult> checks;

  bool ok() const;
  // One line per check: "[PASS] name: message".
  std::string ToString() const;
  nlohmann::json ToJson() const;
};

// Runs every check; never throws for a failing env (an exception escaping
// the env is recorded as a failed check). Checks:
//  - spaces are well formed, info fields unique;
//  - same seeds give identical trajectories (obs, reward, flags, info,
//    bitwise) on two instances; different env or task seeds differ (an env
//    whose spec says uses_env_seed = false must instead give identical
//    trajectories for different env seeds);
//  - every observation lies in its space, rewards and info are finite;
//  - task states round-trip through JSON text exactly and reproduce the same
//    trajectory on another instance; a foreign or malformed state is rejected
//    with TaskStateError;
//  - errors are raised: step before reset, step after the episode ended,
//    wrong action length, NaN/inf actions, out-of-space discrete actions;
//    Box actions outside the bounds are clipped (same as the clipped action).
CheckReport CheckEnv(const std::function<std::unique_ptr<Env>()>& make_env,
                     const CheckOptions& options = {});

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_ENV_CHECKER_H_
