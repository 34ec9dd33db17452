// drawer-close: push an open drawer shut until the object point is within
// 0.065 m of the goal (Meta-World v3, reward version "v2").
//   cabinet obj_pos in [(-0.1, 0.9, 0), (0.1, 0.9, 0)]; the drawer starts
//     pulled out 0.15 m; the object point (obs[4:7]) is 1 cm in front of and
//     5 cm above the handle bar's centre, as v3's, so it is 0.051 m from the
//     goal even when shut; goal = the shut bar = obj_pos + (0, -0.16, 0.09),
//     so success needs the drawer pushed to within 0.0315 m of shut; hand
//     starts at (0, 0.6, 0.2); obs[7:11] zeros (as v3)
//   in_place = tol(|handle - goal|, (0, 0.05),
//     margin ||obj_init - goal| - 0.05|) (obj_init = the point at reset)
//   reach = H(tolG(|handle - tcp|, (0, 0.005),
//     margin ||obj_init - tcp_init| - 0.005|), clip(a[3], 0, 1))
//   reward = 10 H(reach, in_place); 10 on success
//   info: success |handle - goal| <= 0.065; near_object |handle - tcp|
//     <= 0.01; grasp_success 1 (as v3); grasp_reward = reach;
//     in_place_reward = in_place; obj_to_target = |handle - goal|.
//   (tol: long-tail, tolG: gaussian tolerance; H: Hamacher product.)
//   v1: reward = -|tcp - obj| + (|tcp - obj| < 0.05 ? max(progress(|obj.y -
//     goal.y|), 0) : 0), max_dist 0.15 (maxDist); info from v1's zeros:
//     success |obj.y - goal.y| <= 0.065, near_object 1, grasp_success 1.
#ifndef MANYWORLDS_MANIPULATION_DRAWER_DRAWER_CLOSE_H_
#define MANYWORLDS_MANIPULATION_DRAWER_DRAWER_CLOSE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class DrawerClose : public ArticulatedTask {
 public:
  explicit DrawerClose(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Comes down in front of the handle with the gripper closed and pushes it
// in.
class DrawerCloseScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DRAWER_DRAWER_CLOSE_H_
