// push-wall (Meta-World v3): move the puck around (or over) a wall to a goal
// on the table behind it.
//   goal xy in (-0.05, 0.85)-(0.05, 0.9), at the puck's starting height
//   reward (v3): g = caging (high density; radius 0.015, pads 0.05, xz
//     0.005); 2 g, or with the tcp within 2 cm and the gripper not shut
//     2 g + 1 + 4 tol(|(puck - midpoint) (3, 1, 1)|, (0, 0.05)) toward the
//     midpoint (-0.05, 0.77) past the wall's end, and once the puck is past
//     y 0.75, 2 g + 5 + 3 tol(|puck - goal|, (0, 0.05)); 10 within 0.05.
//   info: success |puck - goal| <= 0.07; in_place_reward = the goal term.
//   v1: reward = -|tcp - obj| + max(progress(xy distance to the goal), 0)
//     within 5 cm, max_dist = |obj_init - goal| in xy (maxPushDist); info
//     from v1's zeros: success xy distance <= 0.07, near_object 1,
//     grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_PUSH_PUSH_WALL_H_
#define MANYWORLDS_MANIPULATION_PUSH_PUSH_WALL_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class PushWall : public SawyerTask {
 public:
  explicit PushWall(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the puck, lifts it over the wall and sets it on the goal.
class PushWallScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PUSH_PUSH_WALL_H_
