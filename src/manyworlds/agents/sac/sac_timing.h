// Throughput probe for the SAC update, for the CLI and benchmarks.
#ifndef MANYWORLDS_AGENTS_SAC_SAC_TIMING_H_
#define MANYWORLDS_AGENTS_SAC_SAC_TIMING_H_

#include <cstdint>
#include <vector>

#include "manyworlds/agents/sac/sac_config.h"

namespace manyworlds::agents {

struct SacTimingResult {
  double updates_per_s = 0.0;   // median of samples
  std::vector<double> samples;  // updates per second of each repeat, in run order
  int update_threads = 1;       // threads the learner ran its update shards on
  // Parameters of the learner's networks: actor, the two online critics, and
  // the task encoder and mixture encoder where the architecture has them (0 otherwise).
  int64_t actor_params = 0, critic_params = 0, task_encoder_params = 0, mixture_params = 0;
};

// Builds a SacLearner(config, obs_dim, action_dim, num_tasks), runs 3
// warm-up updates, then times `repeats` runs of `updates` updates each on
// random batches of config.batch_size (drawn beforehand and cycled, task
// indices uniform over the tasks, so only the update is timed). Throws
// ConfigError on a bad config, non-positive dims, updates < 1 or repeats < 1.
SacTimingResult MeasureSacUpdates(const SacConfig& config, int obs_dim, int action_dim,
                                  int num_tasks, int updates, int repeats);

// One repeat of MeasureSacUpdates: updates per second.
double TimeSacUpdates(const SacConfig& config, int obs_dim, int action_dim, int num_tasks,
                      int updates);

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_SAC_SAC_TIMING_H_
