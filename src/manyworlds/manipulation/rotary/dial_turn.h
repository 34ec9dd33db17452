// dial-turn: turn a dial on the table (Meta-World v3, reward version "v2").
//   dial obj_pos in (-0.1, 0.7, 0)-(0.1, 0.8, 0); it turns about z through
//     obj_pos (assets/dial_turn.xml); goal = obj_pos + (0, 0.03, 0.03); hand
//     starts at (0, 0.6, 0.2) (all as v3)
//   object point (obs[4:7]) = obj_pos + 0.05 (sin a, -cos a, 0) at the dial's
//     angle a, as v3 computes it; obs[7:11] the base's (w, x, y, z) =
//     (1, 0, 0, 0), as v3's body "dial"
//   push = obj + (0.05, 0.02, 0.09) (v3's dial_push_position); push_init is
//     its value at reset (the record's handle_init)
//   in_place = tol(|obj - goal|, (0, 0.07), margin | |push_init - goal| - 0.07 |)
//   reach = H(gaussian(|push - tcp|, (0, 0.005), margin
//     | |push_init - tcp_init| - 0.005 |), clip(a[3], 0, 1))
//   reward = 10 H(reach, in_place)
//   info: success |obj - goal| <= 0.07 (the dial turned 1.37 rad either way,
//     as in v3); near_object |push - tcp| <= 0.01; grasp_success 1;
//     grasp_reward reach; in_place_reward in_place; obj_to_target |obj - goal|.
//   (tol: long-tail tolerance; H: Hamacher product.)
//   v1: reward = -|tcp - obj| + max(progress(|obj.y - goal.y|), 0) within
//     5 cm, max_dist = |goal.y - obj_init.y| (maxPullDist); info from v1's
//     zeros: success <= 0.07, near_object 1, grasp_success 1.
#ifndef MANYWORLDS_MANIPULATION_ROTARY_DIAL_TURN_H_
#define MANYWORLDS_MANIPULATION_ROTARY_DIAL_TURN_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class DialTurn : public ArticulatedTask {
 public:
  explicit DialTurn(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  // handle_init = v3's dial_push_position at reset (the object point + (0.05, 0.02, 0.09)).
  void InitTaskState(SawyerState& state) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
};

// Pushes the dial's ridge clockwise with the closed gripper.
class DialTurnScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_ROTARY_DIAL_TURN_H_
