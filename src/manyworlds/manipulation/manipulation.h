// The manipulation suite: Sawyer-style tasks with Meta-World mechanics.
//
//   Registry registry;
//   manipulation::RegisterManipulationSuite(registry);
//   auto env = registry.Make("pick-place", {{"goal_observable", false}});
//
// Registered ids, in order: reach, push, pick-place, door-open, drawer-open,
// drawer-close, button-press-topdown, peg-insert-side, window-open,
// window-close, sweep, basketball, door-close, shelf-place, sweep-into,
// lever-pull (family "manipulation"). Options:
//   goal_observable (bool, default true): goal in obs[36:39] and the task
//     observation; false zeroes it (meta-RL setting).
//   throw_on_sim_warning (bool, default false): MuJoCo warnings during a
//     step throw instead of truncating the episode.
#ifndef MANYWORLDS_MANIPULATION_MANIPULATION_H_
#define MANYWORLDS_MANIPULATION_MANIPULATION_H_

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "manyworlds/core/policy.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

// Registers every task, then the benchmarks (mt10, ml10, mt1, ml1; see
// benchmark.h).
void RegisterManipulationSuite(Registry& registry);

// Ids of the tasks RegisterManipulationSuite adds, in order.
std::vector<std::string> ManipulationTaskIds();

// A task by id, as its concrete class. Throws ConfigError for an unknown id.
std::unique_ptr<SawyerTask> MakeSawyerTask(std::string_view task_id, SawyerOptions options = {});

// The scripted (expert) policy of a task, acting from observations with the
// goal observable. Throws ConfigError for an unknown id.
std::unique_ptr<Policy> MakeScriptedPolicy(std::string_view task_id);

}  // namespace manyworlds::manipulation

namespace manyworlds {
using manipulation::RegisterManipulationSuite;
}  // namespace manyworlds

#endif  // MANYWORLDS_MANIPULATION_MANIPULATION_H_
