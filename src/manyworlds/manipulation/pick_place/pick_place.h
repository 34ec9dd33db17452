// pick-place: grasp the puck and bring it within 7 cm of a goal in space.
//   puck in [(-0.1, 0.6, 0.02), (0.1, 0.7, 0.02)]
//   goal in [(-0.1, 0.8, 0.05), (0.1, 0.9, 0.3)], >= 0.15 m from the puck
//     in xy
//   in_place = tol(|obj - goal|, (0, 0.05), margin |obj_init - goal|)
//   grasped = gripper caging, (H(caging, gripping) + caging) / 2
//   reward = H(grasped, in_place); + 1 + 5 in_place when |obj - tcp| < 0.02,
//     opening > 0 and the puck is 1 cm above its start; 10 once
//     |obj - goal| < 0.05
//   info: success |obj - goal| <= 0.07; near_object |tcp - obj| <= 0.03;
//     grasp_success = touching and opening > 0 and lifted 2 cm;
//     grasp_reward = grasped; in_place_reward; obj_to_target = |obj - goal|.
//   v1: reach (xy first, tcp height change weighted 2; + max(a[3], 0) / 50
//     within 5 cm), + 100 lift target once lifted, + max(progress(|obj -
//     goal|), 0) while lifted, near and not dropped (v1::PickPlace; lift
//     target 4 cm above the puck's start); info from v1's zeros: success
//     |obj - goal| <= 0.07, near_object 1, grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_PICK_PLACE_PICK_PLACE_H_
#define MANYWORLDS_MANIPULATION_PICK_PLACE_PICK_PLACE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class PickPlace : public SawyerTask {
 public:
  explicit PickPlace(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state,
                            std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the puck, lifts it and carries it to the goal.
class PickPlaceScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PICK_PLACE_PICK_PLACE_H_
