// Helpers shared by the classic env tests.
#ifndef MANYWORLDS_TESTS_CLASSIC_TEST_UTIL_H_
#define MANYWORLDS_TESTS_CLASSIC_TEST_UTIL_H_

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "manyworlds/classic/classic.h"
#include "manyworlds/core/env.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/core/rng.h"

namespace manyworlds::classic::testing {

inline const Registry& ClassicRegistry() {
  static const Registry registry = [] {
    Registry r;
    RegisterClassicSuite(r);
    return r;
  }();
  return registry;
}

inline std::unique_ptr<Env> Make(const std::string& id,
                                 const nlohmann::json& options = nlohmann::json::object()) {
  return ClassicRegistry().Make(id, options);
}

// Everything an env reports over `steps` random-action steps (resetting at
// episode ends), flattened, for bitwise comparison.
inline std::vector<float> Rollout(Env& env, int steps, uint64_t action_seed = 5) {
  Rng action_rng(action_seed);
  std::vector<float> trace;
  auto append = [&](const std::vector<float>& v) { trace.insert(trace.end(), v.begin(), v.end()); };
  Observation obs = env.Reset();
  append(obs.env_obs);
  append(obs.task_obs);
  for (int i = 0; i < steps; ++i) {
    StepResult r = env.Step(env.spec().action_space.Sample(action_rng));
    append(r.obs.env_obs);
    append(r.obs.task_obs);
    append(r.info.values);
    trace.push_back(r.reward);
    trace.push_back(r.terminated ? 1.0f : 0.0f);
    trace.push_back(r.truncated ? 1.0f : 0.0f);
    if (r.terminated || r.truncated) {
      obs = env.Reset();
      append(obs.env_obs);
      append(obs.task_obs);
    }
  }
  return trace;
}

// Seeds an env and sets the task drawn from task_seed.
inline void SeedBoth(Env& env, uint64_t seed, uint64_t task_seed) {
  env.Seed(seed);
  env.SeedTask(task_seed);
  env.ResetTaskState();
}

inline bool AllZero(std::span<const float> values) {
  for (float v : values) {
    if (v != 0.0f) return false;
  }
  return true;
}

}  // namespace manyworlds::classic::testing

#endif  // MANYWORLDS_TESTS_CLASSIC_TEST_UTIL_H_
