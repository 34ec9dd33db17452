// drawer-open: pull a drawer out of its cabinet by the handle until the
// object point is within 0.03 m of the goal (Meta-World v3, reward version
// "v2").
//   cabinet obj_pos in [(-0.1, 0.9, 0), (0.1, 0.9, 0)]; the object point
//     (obs[4:7]) is 1 cm in front of the handle bar's centre, at
//     obj_pos + (0, -0.17, 0.09) when shut; goal = obj_pos + (0, -0.36, 0.09)
//     (v3: the point pulled out 0.2 m minus 1 cm), so success needs the
//     drawer pulled out >= 0.16 m of its 0.2 m; hand starts at (0, 0.6, 0.2);
//     obs[7:11] the handle's (w, x, y, z) orientation
//   opening = tol(|handle - goal|, (0, 0.02), margin 0.2)
//   caging = tol(|(handle - hand) * (3, 3, 1)|, (0, 0.01),
//     margin |(goal + (0, 0.2, 0) - tcp_init) * (3, 3, 1)|) (hand = obs[0:3])
//   reward = 5 (caging + opening) (at most 10; no success bonus)
//   info: success |handle - goal| <= 0.03; near_object |handle - hand|
//     <= 0.03; grasp_success = obs[3] > 0; grasp_reward = caging;
//     in_place_reward = opening; obj_to_target = |handle - goal|.
//   (tol: long-tail tolerance.)
//   v1: reward = -|tcp - obj| + (|tcp - obj| < 0.05 ? max(progress(|obj.y -
//     goal.y|), 0) : 0), max_dist 0.2 (maxDist); info from v1's zeros:
//     success |obj.y - goal.y| <= 0.03, near_object 1, grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_DRAWER_DRAWER_OPEN_H_
#define MANYWORLDS_MANIPULATION_DRAWER_DRAWER_OPEN_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class DrawerOpen : public ArticulatedTask {
 public:
  explicit DrawerOpen(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the handle bar (gripper half open on the way down: the drawer face
// is close behind the bar) and pulls it out to the drawer's stop.
class DrawerOpenScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DRAWER_DRAWER_OPEN_H_
