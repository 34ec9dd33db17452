// The box world's scripted (expert) policy; BoxWorldEnv::CreateScriptedPolicy
// hands it out.
#ifndef MANYWORLDS_BOXWORLD_SCRIPTED_POLICY_H_
#define MANYWORLDS_BOXWORLD_SCRIPTED_POLICY_H_

#include <memory>

#include "manyworlds/boxworld/box_world_env.h"
#include "manyworlds/core/policy.h"

namespace manyworlds::boxworld {

// A privileged scripted policy reading the env's state (it sees the target
// even with hide_target): simple task, drive to the target; complex task,
// take the undelivered boxes in turn, get behind each (on the side away
// from the target) and push it along the line to the target. `env` must
// outlive it.
std::unique_ptr<Policy> MakeScriptedPolicy(const BoxWorldEnv& env);

}  // namespace manyworlds::boxworld

#endif  // MANYWORLDS_BOXWORLD_SCRIPTED_POLICY_H_
