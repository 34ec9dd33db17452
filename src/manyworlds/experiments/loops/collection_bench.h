// Collection throughput of a training config against the raw executor:
// `manyworlds bench collect CONFIG`. Both arms step the same envs on the
// same threads (the Collector's executor), interleaved repeat by repeat:
//   env         executor Step with uniform random actions, nothing else;
//   collection  the algorithm's own iteration (policy forward for all envs
//               in one batched inference-mode call, action mapping, episode
//               bookkeeping, rollout or replay writes), timing the acting
//               and stepping parts only (time_act_s + time_env_s of its
//               metrics row; the update is excluded).
#ifndef MANYWORLDS_EXPERIMENTS_LOOPS_COLLECTION_BENCH_H_
#define MANYWORLDS_EXPERIMENTS_LOOPS_COLLECTION_BENCH_H_

#include <cstdint>
#include <vector>

#include "manyworlds/experiments/train_config.h"

namespace manyworlds::experiments {

struct CollectionBenchResult {
  int64_t num_envs = 0;
  int num_threads = 0;
  int64_t steps_per_repeat = 0;  // env steps (all envs) per arm per repeat
  std::vector<double> env_steps_per_s;         // per repeat
  std::vector<double> collection_steps_per_s;  // per repeat
  double env_median = 0.0;
  double collection_median = 0.0;
  double ratio = 0.0;  // median of per-repeat collection / env ratios
};

// Throws ConfigError on a bad config (as the Trainer would).
CollectionBenchResult MeasureCollection(const TrainConfig& config, int repeats);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_LOOPS_COLLECTION_BENCH_H_
