// The default registry with every suite manyworlds ships, and the Gym-style
// entry point:
//
//   std::unique_ptr<Env> env = manyworlds::Make("cartpole");
//   std::unique_ptr<Env> bandit = manyworlds::Make("bandit", {{"n_arms", 5}});
#ifndef MANYWORLDS_ENVS_ALL_H_
#define MANYWORLDS_ENVS_ALL_H_

#include <memory>
#include <string_view>

#include <nlohmann/json.hpp>

#include "manyworlds/core/env.h"
#include "manyworlds/core/registry.h"

namespace manyworlds {

// Built on first use (thread-safe) and never modified afterwards, so it may
// be read from any thread.
const Registry& DefaultRegistry();

// DefaultRegistry().Make(id, options). Throws ConfigError for an unknown id
// (suggesting the nearest ones) or a bad option.
std::unique_ptr<Env> Make(std::string_view id, const nlohmann::json& options = {});

}  // namespace manyworlds

#endif  // MANYWORLDS_ENVS_ALL_H_
