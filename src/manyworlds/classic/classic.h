// The classic multi-task / meta-RL suite: small, fast envs with
// well-understood optima, for testing agents and the multi-task machinery.
//
//   bandit            Bernoulli multi-armed bandit
//   tabular-mdp       random tabular MDP
//   two-goal-maze     grid T-maze, which end pays is the task
//   cartpole          cart-pole with task-dependent physics
//   acrobot           acrobot with task-dependent links
//   point-nav         2-D point navigation, dense reward
//   point-nav-sparse  2-D point navigation to a half-circle goal, sparse
//
// Every id is in family "classic" and takes option hide_task (bool, default
// false): the task observation is then all zeros (the meta-RL setting, where
// the agent must infer the task from experience).
#ifndef MANYWORLDS_CLASSIC_CLASSIC_H_
#define MANYWORLDS_CLASSIC_CLASSIC_H_

#include "manyworlds/core/registry.h"

namespace manyworlds {

// Adds the seven ids above. Throws ConfigError if one is already registered.
void RegisterClassicSuite(Registry& registry);

}  // namespace manyworlds

#endif  // MANYWORLDS_CLASSIC_CLASSIC_H_
