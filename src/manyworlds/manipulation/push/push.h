// push: move the puck over the table to within 5 cm of a goal on the table.
//   puck in [(-0.1, 0.6, 0.02), (0.1, 0.7, 0.02)]
//   goal in [(-0.1, 0.8, ·), (0.1, 0.9, ·)], height = the puck's, >= 0.15 m
//     from the puck in xy
//   in_place = tol(|obj - goal|, (0, 0.05), margin |obj_init - goal|)
//   grasped = gripper caging (high density; obj radius 0.015, pad 0.05,
//     xz 0.005)
//   reward = 2 grasped; if |obj - tcp| < 0.02 and opening > 0:
//     reward = 2 reward + 1 + 5 in_place; 10 once |obj - goal| < 0.05
//   info: success |obj - goal| <= 0.05; near_object |tcp - obj| <= 0.03;
//     grasp_success = touching and opening > 0 and lifted 2 cm;
//     grasp_reward = grasped; in_place_reward; obj_to_target = |obj - goal|.
//   v1: reward = -|tcp - obj| + (|tcp - obj| < 0.05 ? max(progress(xy
//     distance to the goal), 0) : 0), max_dist = |obj_init - goal| in xy
//     (maxPushDist); info from v1's zeros: success xy distance <= 0.05,
//     near_object 1, grasp_success 0, obj_to_target the xy distance.
#ifndef MANYWORLDS_MANIPULATION_PUSH_PUSH_H_
#define MANYWORLDS_MANIPULATION_PUSH_PUSH_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class Push : public SawyerTask {
 public:
  explicit Push(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state,
                            std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the puck and slides it to the goal just above the table.
class PushScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PUSH_PUSH_H_
