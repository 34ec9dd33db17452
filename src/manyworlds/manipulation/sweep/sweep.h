// sweep: slide the puck sideways along the table into the goal zone at the
// table's +x edge.
//   puck in [(-0.1, 0.6, 0.02), (0.1, 0.7, 0.02)]
//   goal in [(0.49, 0.6, 0), (0.51, 0.7, 0.02)] (always >= 0.39 m away)
//   in_place = tol(|obj - goal|, (0, 0.05), margin |obj_init - goal|)
//   grasped = gripper caging (high density; obj radius 0.02, pad 0.05,
//     xz 0.005)
//   reward = 2 grasped + 6 H(grasped, in_place); 10 once |obj - goal| < 0.05
//   info: success |obj - goal| <= 0.05; near_object |tcp - obj| <= 0.03;
//     grasp_success = a pad touches the puck, opening > 0 and tcp within
//     2 cm of it (the puck stays on the table); grasp_reward = grasped;
//     in_place_reward; obj_to_target = |obj - goal|.
//   v1: reward = -|tcp - obj| + max(progress(xy distance to the goal), 0)
//     within 5 cm, both terms' distances 0 once the puck is 5 cm below its
//     start, max_dist = |obj_init - goal| in xy (maxPushDist); info from
//     v1's zeros: success distance <= 0.05, near_object 1.
#ifndef MANYWORLDS_MANIPULATION_SWEEP_SWEEP_H_
#define MANYWORLDS_MANIPULATION_SWEEP_SWEEP_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class Sweep : public SawyerTask {
 public:
  explicit Sweep(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
  Vec3 DeriveGoal(const Vec3& obj, const Vec3& drawn_goal) const override;
};

// Closes on the puck and slides it, 5 mm above the table, to the goal.
class SweepScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_SWEEP_SWEEP_H_
