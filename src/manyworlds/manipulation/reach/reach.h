// reach: bring the gripper's tcp within 5 cm of a goal in space.
//   object (distractor) in [(-0.1, 0.6, 0.02), (0.1, 0.7, 0.02)]
//   goal in [(-0.1, 0.8, 0.05), (0.1, 0.9, 0.3)], >= 0.15 m from it in xy
//   reward = 10 tol(|tcp - goal|, (0, 0.05), margin |hand_init - goal|)
//   info: success |tcp - goal| <= 0.05; near_object, grasp_reward and
//     obj_to_target = |tcp - goal|; grasp_success = 1;
//     in_place_reward = the tolerance term.
//   v1: reward = max(progress(|tcp - goal|), 0) with max_dist = |tcp_init -
//     goal| (maxReachDist); info as above with in_place_reward 0.
#ifndef MANYWORLDS_MANIPULATION_REACH_REACH_H_
#define MANYWORLDS_MANIPULATION_REACH_REACH_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class Reach : public SawyerTask {
 public:
  explicit Reach(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state,
                            std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Moves the tcp straight to the observed goal (needs an observable goal).
class ReachScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_REACH_REACH_H_
