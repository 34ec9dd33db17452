// drawer-open: pull a drawer out of its cabinet by the handle until the
// handle is within 0.03 m of the goal (metaworld.md §2.9).
//   cabinet obj_pos in [(-0.1, 0.9, 0), (0.1, 0.9, 0)]; the closed handle is
//     at obj_pos + (0, -0.16, 0.09); goal = the handle pulled out 0.2 m =
//     obj_pos + (0, -0.36, 0.09) (as the reference); hand starts at
//     (0, 0.6, 0.2)
//   reach = tol(|tcp - handle|, (0, 0.02), margin |tcp_init - handle_init|)
//   engaged = H(reach, grip effort (a[3] + 1) / 2)
//   in_place = tol(|handle - goal|, (0, 0.03), margin |handle_init - goal|)
//   reward = 2 engaged + 8 in_place; 10 on success
//   info: success |handle - goal| <= 0.03; near_object |tcp - handle|
//     <= 0.03; grasp_success = a pad touches the handle and a[3] > 0;
//     grasp_reward = engaged; in_place_reward; obj_to_target =
//     |handle - goal|.
#ifndef MANYWORLDS_MANIPULATION_DRAWER_OPEN_H_
#define MANYWORLDS_MANIPULATION_DRAWER_OPEN_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class DrawerOpen : public ArticulatedTask {
 public:
  explicit DrawerOpen(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Grasps the handle bar (gripper half open on the way down: the drawer face
// is close behind the bar) and pulls it to the goal.
class DrawerOpenScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DRAWER_OPEN_H_
