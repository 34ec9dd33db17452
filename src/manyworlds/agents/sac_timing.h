// Throughput probe for the SAC update, for the CLI and benchmarks.
#ifndef MANYWORLDS_AGENTS_SAC_TIMING_H_
#define MANYWORLDS_AGENTS_SAC_TIMING_H_

#include "manyworlds/agents/sac_config.h"

namespace manyworlds::agents {

// Builds a SacLearner, runs 3 warm-up updates, then times `updates` updates
// on random batches of config.batch_size (drawn beforehand, so only the
// update is timed) and returns updates per second. Throws ConfigError on a
// bad config, non-positive dims or updates < 1.
double TimeSacUpdates(const SacConfig& config, int obs_dim, int action_dim, int num_tasks,
                      int updates);

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_SAC_TIMING_H_
