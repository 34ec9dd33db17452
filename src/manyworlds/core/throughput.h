// Env throughput measurement through BatchedExecutor (used by
// `manyworlds bench env` and the benchmarks).
//
//   ThroughputResult r = MeasureThroughput(
//       [](int) { return registry.Make("cartpole"); },
//       {.num_envs = 8, .num_threads = 2, .steps = 1'000'000, .repeats = 5, .seed = 0});
//   std::cout << r.steps_per_s;
//
// Actions are sampled before timing from each env's action space (a small
// pool of action batches, cycled), so only stepping is measured. Auto-reset
// is on, so resets at episode ends are part of the cost, as in training.
#ifndef MANYWORLDS_CORE_THROUGHPUT_H_
#define MANYWORLDS_CORE_THROUGHPUT_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "manyworlds/core/env.h"

namespace manyworlds {

struct ThroughputOptions {
  int num_envs = 1;        // >= 1
  int num_threads = 1;     // >= 1
  int64_t steps = 100000;  // env steps in total per repeat (rounded up to whole batches)
  int repeats = 5;         // >= 1
  uint64_t seed = 0;       // env, task and action seeds derive from it
};

struct ThroughputResult {
  double steps_per_s = 0.0;     // median over repeats
  std::vector<double> samples;  // env steps/s of each repeat, in order
  double min_steps_per_s = 0.0;
  double max_steps_per_s = 0.0;
  double ns_per_step = 0.0;      // 1e9 / steps_per_s: wall time per env step
  int64_t steps_per_repeat = 0;  // env steps actually run per repeat
  int num_envs = 0;
  int num_threads = 0;  // threads the executor really used
};

// Builds opts.num_envs envs with make_env(i), then times BatchedExecutor::Step
// after a warm-up. Throws ConfigError on bad options or a null env; errors of
// the envs propagate.
ThroughputResult MeasureThroughput(
    const std::function<std::unique_ptr<Env>(int env_index)>& make_env,
    const ThroughputOptions& opts);

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_THROUGHPUT_H_
