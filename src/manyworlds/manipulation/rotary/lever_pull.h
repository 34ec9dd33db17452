// lever-pull: pull a lever from pointing at the robot up to vertical, to
// within pi/24 (Meta-World v3, reward version "v2").
//   lever post obj_pos in [(-0.1, 0.7, 0), (0.1, 0.8, 0)]; the lever turns
//     about an x axis at obj_pos + (0.12, 0, 0.25) and its 0.2 m arm ends in a
//     grip (obs[4:7]), at obj_pos + (0.12, -0.2, 0.25) at rest; goal = the
//     grip with the lever up = obj_pos + (0.12, 0, 0.45) (all as v3); hand
//     starts at (0, 0.4, 0.2); the observation bounds the goal by v3's hand
//     bounds, (-0.5, 0.4, -0.15)-(0.5, 1, 0.5) (ours stop at z 0.05)
//   With angle = -joint_qpos (the lever's angle up from rest),
//   shoulder = (hand + (0, 0.055, 0.07) - grip) * (4, 1, 4) (hand = obs[0:3])
//   ready = tol(|shoulder|, (0, 0.02),
//     margin |(tcp_init + (0, 0.055, 0.07) - handle_init) * (4, 1, 4)|)
//   in_place = tol(|grip - goal|, (0, 0.04), margin |handle_init - goal|)
//   engagement = tol(|angle - pi/2|, (0, pi/48), margin pi/2 - pi/12)
//   reward = 10 H(ready, in_place) (no success bonus)
//   info: success |angle - pi/2| <= pi/24; near_object |shoulder| < 0.03;
//     grasp_success = ready > 0.9; grasp_reward = ready; in_place_reward =
//     engagement; obj_to_target = |shoulder| (as v3 reports them).
//   (tol: long-tail tolerance; H: Hamacher product.)
//   v1: reward = -|tcp - obj| + max(progress(|obj - goal|), 0) within 5 cm,
//     max_dist = |goal - obj_init| (maxPullDist); info from v1's (reward, 0,
//     0, |obj - goal|, 0): success |obj - goal| <= pi/24 (v3 reads the
//     distance as its angle error), near_object 1, the rest 0.
#ifndef MANYWORLDS_MANIPULATION_ROTARY_LEVER_PULL_H_
#define MANYWORLDS_MANIPULATION_ROTARY_LEVER_PULL_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class LeverPull : public ArticulatedTask {
 public:
  explicit LeverPull(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the grip beside the arm and carries it up around the lever's axis
// (found from the goal).
class LeverPullScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_ROTARY_LEVER_PULL_H_
