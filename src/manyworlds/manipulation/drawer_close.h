// drawer-close: push an open drawer shut until the handle is within
// 0.065 m of its closed position (metaworld.md §2.9).
//   cabinet obj_pos in [(-0.1, 0.9, 0), (0.1, 0.9, 0)]; the drawer starts
//     pulled out 0.2 m; goal = the closed handle = obj_pos + (0, -0.16, 0.09);
//     hand starts at (0, 0.6, 0.2)
//   reward (MoveHandleReward in articulated.h, radius 0.065):
//     reach = tol(d, (0, 0.02), margin |tcp_init - handle_init|), d = the
//       distance from the handle to the nearest of tcp and pads
//     in_place = tol(|handle - goal|, (0, 0.065), margin |handle_init - goal|)
//     reward = 2 reach + 8 in_place; 10 on success
//   info: success |handle - goal| <= 0.065; near_object d <= 0.03;
//     grasp_success = a pad touches the handle; grasp_reward = reach;
//     in_place_reward; obj_to_target = |handle - goal|.
#ifndef MANYWORLDS_MANIPULATION_DRAWER_CLOSE_H_
#define MANYWORLDS_MANIPULATION_DRAWER_CLOSE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class DrawerClose : public ArticulatedTask {
 public:
  explicit DrawerClose(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Comes down in front of the handle with the gripper closed and pushes it
// in.
class DrawerCloseScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DRAWER_CLOSE_H_
