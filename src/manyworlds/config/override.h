// Hydra-style dotted overrides of a configuration tree:
//
//   ApplyOverride(config, "rollout.episodes=20");   // replace an existing key
//   ApplyOverride(config, "envs=[cartpole,bandit]"); // any YAML flow value
//   ApplyOverride(config, "+extra.note=hello");     // add a key that is absent
//   ApplyOverride(config, "++seed=3");              // add or replace
//
// The value is read as YAML (`0.5` is a float, `true` a bool, `foo` a
// string); an empty value is the empty string. Path segments that are
// integers index into lists.
#ifndef MANYWORLDS_CONFIG_OVERRIDE_H_
#define MANYWORLDS_CONFIG_OVERRIDE_H_

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace manyworlds {

// Throws ConfigError for a malformed override (no '=', empty path segment),
// for a plain override of a key that does not exist (naming the nearest
// keys), and for '+' on a key that already exists.
void ApplyOverride(nlohmann::json& config, std::string_view override_text);

// Applies each override in order.
void ApplyOverrides(nlohmann::json& config, const std::vector<std::string>& overrides);

}  // namespace manyworlds

#endif  // MANYWORLDS_CONFIG_OVERRIDE_H_
