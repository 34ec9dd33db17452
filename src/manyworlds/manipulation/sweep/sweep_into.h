// sweep-into: slide the puck across the table into the goal pocket (three
// low walls around the goal, open toward the robot).
//   puck in [(-0.1, 0.6, 0.02), (0.1, 0.7, 0.02)]
//   goal fixed at (0, 0.84, 0.02), >= 0.15 m from the puck in xy; the
//     pocket's mouth is at y = 0.785, so success means the puck is in it
//   in_place = tol(|obj - goal|, (0, 0.05), margin |obj_init - goal|)
//   grasped = gripper caging (high density; obj radius 0.02, pad 0.05,
//     xz 0.005)
//   reward = H(grasped, in_place); + 1 + 7 in_place while the tcp is within
//     2 cm of the puck and opening > 0; 10 once |obj - goal| < 0.05
//   info: success |obj - goal| <= 0.05; near_object |tcp - obj| <= 0.03;
//     grasp_success = a pad touches the puck, opening > 0 and tcp within
//     2 cm of it; grasp_reward = grasped; in_place_reward;
//     obj_to_target = |obj - goal|.
//   v1: reward = -|tcp - obj| + max(progress(xy distance to the goal), 0)
//     within 5 cm, both distances 0 once the puck has dropped 5 cm (with
//     0.4 < y < 1), max_dist = |obj_init - goal| in xy (maxPushDist); info
//     from v1's zeros: success distance <= 0.05, near_object 1.
#ifndef MANYWORLDS_MANIPULATION_SWEEP_SWEEP_INTO_H_
#define MANYWORLDS_MANIPULATION_SWEEP_SWEEP_INTO_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class SweepInto : public SawyerTask {
 public:
  explicit SweepInto(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Closes on the puck and slides it, 5 mm above the table, into the pocket.
class SweepIntoScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_SWEEP_SWEEP_INTO_H_
