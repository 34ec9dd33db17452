// Registers the box world suite (family "boxworld"): box-world-simple and
// box-world-complex, whose options are the generator's ranges
// (docs/boxworld.md), and gives its scripted policy.
#ifndef MANYWORLDS_BOXWORLD_BOXWORLD_H_
#define MANYWORLDS_BOXWORLD_BOXWORLD_H_

#include <memory>

#include "manyworlds/boxworld/box_world_env.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/core/registry.h"

namespace manyworlds {

void RegisterBoxWorldSuite(Registry& registry);

namespace boxworld {

// The box world env inside `env` (itself or under wrappers), or null.
const BoxWorldEnv* FindBoxWorld(const Env& env);

// A privileged scripted policy reading the env's state (it sees the target
// even with hide_target): simple task, drive to the target; complex task,
// take the undelivered boxes in turn, get behind each (on the side away
// from the target) and push it along the line to the target. `env` must
// outlive it. Returns null if `env` is not a box world.
std::unique_ptr<Policy> MakeScriptedPolicy(const Env& env);

}  // namespace boxworld
}  // namespace manyworlds

#endif  // MANYWORLDS_BOXWORLD_BOXWORLD_H_
