// button-press-topdown: press a button on top of a box down until it is
// within 0.02 m of fully pressed (metaworld.md §2.9).
//   button rest position obj_pos in [(-0.1, 0.8, 0.115), (0.1, 0.9, 0.115)];
//     goal = the button pressed in 3.5 cm (flush with the box) =
//     obj_pos + (0, 0, -0.035); hand starts at (0, 0.4, 0.2)
//   reach = tol(|tcp - cap top|, (0, 0.02), margin |tcp_init - cap top at
//     reset|) (the cap top is 2 cm above the button's centre)
//   in_place = tol(|button_z - goal_z|, (0, 0.02), margin 0.035)
//   reward = 2 reach + 8 in_place; 10 on success
//   info: success |button_z - goal_z| <= 0.02; near_object |tcp - cap top|
//     <= 0.03; grasp_success = a pad touches the button; grasp_reward =
//     reach; in_place_reward; obj_to_target = |button_z - goal_z|.
#ifndef MANYWORLDS_MANIPULATION_BUTTON_PRESS_TOPDOWN_H_
#define MANYWORLDS_MANIPULATION_BUTTON_PRESS_TOPDOWN_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class ButtonPressTopdown : public ArticulatedTask {
 public:
  explicit ButtonPressTopdown(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Hovers over the button with the gripper closed, then presses straight down.
class ButtonPressTopdownScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_BUTTON_PRESS_TOPDOWN_H_
