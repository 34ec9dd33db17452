// TimeLimit: truncates episodes after max_episode_steps steps.
//
// The limit is enforced by Env::Step of this wrapper (truncated = true, and
// terminated may be set in the same step, as in Gymnasium). A shorter limit
// of the inner env still applies, so the spec reports the effective limit,
// min(inner limit, max_episode_steps). To lengthen episodes of an env with a
// built-in limit, call SetMaxEpisodeSteps (it changes every level).
#ifndef MANYWORLDS_CORE_WRAPPERS_TIME_LIMIT_H_
#define MANYWORLDS_CORE_WRAPPERS_TIME_LIMIT_H_

#include <cstdint>
#include <memory>

#include "manyworlds/core/wrapper.h"

namespace manyworlds {

class TimeLimit : public Wrapper {
 public:
  // Throws ConfigError if max_episode_steps < 1.
  TimeLimit(std::unique_ptr<Env> inner, int64_t max_episode_steps);
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_TIME_LIMIT_H_
