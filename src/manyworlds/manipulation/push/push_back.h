// push-back (Meta-World v3): bring a 4 cm block from the back of the table
// to a goal in front of it.
//   block in (-0.1, 0.8)-(0.1, 0.85), goal in (-0.1, 0.6)-(0.1, 0.7) at the
//   block's height, >= 0.15 m apart in xy
//   reward (v3): g = its own caging (sweep-style; radius 0.007, grip band
//     3 mm, xz 0.01); H(g, in_place), + 1 + 5 in_place with the tcp within
//     1 cm, the gripper partly closed (0 < obs[3] < 0.55) and the block 1 cm
//     nearer the goal than at the start; 10 within 0.05.
//   info: success |block - goal| <= 0.07.
//   v1: reward = -|tcp - obj| + max(progress(xy distance to the goal), 0)
//     within 5 cm, max_dist = |obj_init - goal| in xy (maxPushDist); info
//     from v1's zeros: success xy distance <= 0.07, near_object 1,
//     grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_PUSH_PUSH_BACK_H_
#define MANYWORLDS_MANIPULATION_PUSH_PUSH_BACK_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class PushBack : public SawyerTask {
 public:
  explicit PushBack(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the block and carries it to the goal just above the table.
class PushBackScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PUSH_PUSH_BACK_H_
