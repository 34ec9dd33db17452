// reach-wall (Meta-World v3): bring the tcp within 5 cm of a goal behind a
// wall; the puck is a distractor.
//   goal in (-0.05, 0.85, 0.05)-(0.05, 0.9, 0.3)
//   reward = 10 tol(|tcp - goal|, (0, 0.05), margin |hand_init - goal|)
//   info: success |tcp - goal| <= 0.05; obj_to_target = |tcp - goal|;
//     in_place_reward = the tolerance; near_object, grasp_success and
//     grasp_reward are 0 (as v3).
//   v1: reward = max(progress(|tcp - goal|), 0), max_dist = |tcp_init -
//     goal| (maxReachDist); info: success <= 0.05, obj_to_target the
//     distance, the rest 0.
#ifndef MANYWORLDS_MANIPULATION_REACH_REACH_WALL_H_
#define MANYWORLDS_MANIPULATION_REACH_REACH_WALL_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class ReachWall : public SawyerTask {
 public:
  explicit ReachWall(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Rises over the wall, then moves to the goal.
class ReachWallScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_REACH_REACH_WALL_H_
