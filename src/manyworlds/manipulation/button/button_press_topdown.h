// button-press-topdown: press a button on top of a box down until its top
// is within 0.024 m of the goal's height (Meta-World v3, reward version
// "v2").
//   box obj_pos in [(-0.1, 0.8, 0.115), (0.1, 0.9, 0.115)]; the cap's top
//     (obs[4:7]) rests at obj_pos + (0, 0, 0.1935) and presses down by up to
//     0.0935 m, to the goal obj_pos + (0, 0, 0.1); success needs a press of
//     0.0695 m; hand starts at (0, 0.4, 0.2); obs[7:11] the cap's (w, x, y, z)
//     orientation
//   near_button = tol(|button - tcp|, (0, 0.01), margin |button - tcp_init|)
//   pressed = tol(|button_z - goal_z|, (0, 0.005), margin obj_to_target_init)
//     (obj_to_target_init = |button_z - goal_z| at reset, 0.0935)
//   reward = 5 H(1 - obs[3], near_button), + 5 pressed when
//     |button - tcp| <= 0.03 (no success bonus)
//   info: success |button_z - goal_z| <= 0.024; near_object |button - tcp|
//     <= 0.05; grasp_success = obs[3] > 0; grasp_reward = near_button;
//     in_place_reward = pressed; obj_to_target = |button_z - goal_z|.
//   (tol: long-tail tolerance; H: Hamacher product.)
//   v1: reward = -|tcp - obj| + max(progress(|obj.z - goal.z|), 0) within
//     5 cm, max_dist = the press depth at reset (maxDist); info from v1's
//     zeros: success <= 0.024, near_object 1, grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_BUTTON_BUTTON_PRESS_TOPDOWN_H_
#define MANYWORLDS_MANIPULATION_BUTTON_BUTTON_PRESS_TOPDOWN_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class ButtonPressTopdown : public ArticulatedTask {
 public:
  explicit ButtonPressTopdown(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  // For a variant on the same button (press/button-press-topdown-wall): its
  // own config (id, model file) with this task's fixture.
  ButtonPressTopdown(SawyerTaskConfig config, SawyerOptions options);
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  // Also obj_to_target_init.
  void InitTaskState(SawyerState& state) const override;
};

// Hovers over the button with the gripper closed, then presses straight down.
class ButtonPressTopdownScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_BUTTON_BUTTON_PRESS_TOPDOWN_H_
