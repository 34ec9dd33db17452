#include "manyworlds/core/wrappers/time_limit.h"

#include <algorithm>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

std::unique_ptr<Env> CheckLimit(std::unique_ptr<Env> inner, int64_t max_episode_steps) {
  if (max_episode_steps < 1) {
    throw ConfigError(
        "wrapper time-limit on env '" + (inner ? inner->id() : std::string("<null>")) +
        "': max_episode_steps must be >= 1, got " + std::to_string(max_episode_steps));
  }
  return inner;
}

}  // namespace

TimeLimit::TimeLimit(std::unique_ptr<Env> inner, int64_t max_episode_steps)
    : Wrapper(CheckLimit(std::move(inner), max_episode_steps),
              "time-limit(" + std::to_string(max_episode_steps) + ")") {
  const int64_t inner_limit = this->inner().spec().max_episode_steps;
  mutable_spec().max_episode_steps =
      inner_limit > 0 ? std::min(inner_limit, max_episode_steps) : max_episode_steps;
}

}  // namespace manyworlds
