// lever-pull: pull a lever from pointing at the robot up to vertical, to
// within pi/24 (metaworld.md §2.9).
//   lever post obj_pos in [(-0.1, 0.7, 0), (0.1, 0.8, 0)]; the lever turns
//     about an x axis at obj_pos + (0.08, 0, 0.2) and its 0.2 m arm ends in a
//     grip, at obj_pos + (0.08, -0.2, 0.2) at rest; goal = the grip with the
//     lever up (angle pi/2) = obj_pos + (0.08, 0, 0.4); hand starts at
//     (0, 0.4, 0.2)
//   reach = tol(|tcp - grip|, (0, 0.04), margin |tcp_init - grip_init|)
//     (the grip is held 3.5 cm to the side of its middle)
//   engaged = H(reach, grip effort (a[3] + 1) / 2)
//   in_place = tol(|angle - pi/2|, (0, pi/24), margin pi/2)
//   reward = 2 engaged + 8 in_place; 10 on success
//   info: success |angle - pi/2| <= pi/24; near_object |tcp - grip| <= 0.05;
//     grasp_success = a pad touches the grip and a[3] > 0; grasp_reward =
//     engaged; in_place_reward; obj_to_target = |angle - pi/2| (radians).
#ifndef MANYWORLDS_MANIPULATION_LEVER_PULL_H_
#define MANYWORLDS_MANIPULATION_LEVER_PULL_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class LeverPull : public ArticulatedTask {
 public:
  explicit LeverPull(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Grasps the grip beside the arm and carries it up around the lever's axis
// (found from the goal).
class LeverPullScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_LEVER_PULL_H_
