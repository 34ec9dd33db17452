// The button tasks of the press family (Meta-World v3, reward version
// "v2"), beside button-press-topdown (../button_press_topdown.h), whose
// button button-press-topdown-wall shares.
//
// button-press, button-press-wall: push a button on the front of a box
// straight in (+y).
//   box obj_pos in [(-0.1, 0.85, 0.115), (0.1, 0.9, 0.115)] (button-press)
//     or [(-0.05, 0.85, 0.1149), (0.05, 0.9, 0.1151)] (-wall); the cap's
//     face (obs[4:7]) rests at obj_pos + (0, -0.193, 0) and goes in by up to
//     0.093 m, to the goal obj_pos + (0, -0.1, 0); hand starts at
//     (0, 0.4, 0.2); obs[7:11] the cap's (w, x, y, z) orientation;
//     obj_to_target_init = 0.0935 (v3 measures it from its button-start
//     site, 0.5 mm in front of the face). button-press-wall: a wall
//     20 x 2 x 15 cm at (0.1, 0.6, 0.075) in front of the button.
//   obj_to_target = |goal_y - button_y|
//   pressed = tol(obj_to_target, (0, 0.005), margin obj_to_target_init)
//   button-press: near = tol(|button - tcp|, (0, 0.05), margin
//     |button - tcp_init|); reward = 2 H(max(obs[3], 0), near), + 8 pressed
//     when |button - tcp| <= 0.05; success obj_to_target <= 0.02.
//   button-press-wall: near = tol(|button - tcp|, (0, 0.01), same margin);
//     reward = 2 H((1 - obs[3]) / 2, near) when |button - tcp| > 0.07, else
//     2 + 2 (1 + obs[3]) + 4 pressed^2; success obj_to_target <= 0.03.
//   info: near_object |button - tcp| <= 0.05; grasp_success obs[3] > 0;
//     grasp_reward = near; in_place_reward = pressed.
//
// button-press-topdown-wall: button-press-topdown's button and ranges with
// a wall 20 x 2 x 15 cm at (0.1, 0.7, 0.075); its reward is
// button-press-topdown's with the gripper term max(obs[3], 0) where
// button-press-topdown has 1 - obs[3]: 5 H(max(obs[3], 0), near) (near
// within 0.01), + 5 pressed when |button - tcp| <= 0.03; success within
// 0.024 of the goal's height.
//   (tol: long-tail tolerance; H: Hamacher product.)
//   v1 (button-press, button-press-wall): reward = -|left finger - obj| +
//     max(progress(|obj.y - goal.y|), 0) within 5 cm, max_dist = the press
//     depth at reset (maxDist; button-press-wall's reads the heights instead,
//     as v3's); info from v1's zeros: success <= 0.02 (wall: 0.03),
//     near_object 1, grasp_success 0. button-press-topdown-wall has
//     button-press-topdown's v1.
#ifndef MANYWORLDS_MANIPULATION_BUTTON_BUTTONS_H_
#define MANYWORLDS_MANIPULATION_BUTTON_BUTTONS_H_

#include <string>

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"
#include "manyworlds/manipulation/button/button_press_topdown.h"

namespace manyworlds::manipulation {

// The front button (button-press and button-press-wall).
class FrontButtonTask : public ArticulatedTask {
 protected:
  FrontButtonTask(SawyerTaskConfig config, SawyerOptions options);
  // Also obj_to_target_init.
  void InitTaskState(SawyerState& state) const override;
  // The front buttons' config: hand start, cap orientation and goal offset shared.
  static SawyerTaskConfig Config(std::string id, std::string description, std::string xml_file,
                                 Vec3 obj_low, Vec3 obj_high);
};

class ButtonPress : public FrontButtonTask {
 public:
  explicit ButtonPress(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// button-press's reward and info (above), from the record: also
// coffee-button's, whose press margin (obj_to_target_init) is v3's max_dist.
RewardTerms ButtonPressReward(const SawyerState& state);
// The front buttons' v1 reward and info (above; also coffee-button's).
RewardTerms FrontButtonRewardV1(const SawyerState& state, double success_radius);

class ButtonPressWall : public FrontButtonTask {
 public:
  explicit ButtonPressWall(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

class ButtonPressTopdownWall : public ButtonPressTopdown {
 public:
  explicit ButtonPressTopdownWall(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Lines the closed fingers up in front of the cap and pushes it in to its
// stop. `clear_height` > 0: first rises to that tcp height, moves over the
// cap's x and then to just in front of it, and comes down there (over a
// wall in front of the button).
class FrontButtonScriptedPolicy : public Policy {
 public:
  explicit FrontButtonScriptedPolicy(double clear_height = 0.0) : clear_height_(clear_height) {}
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;

 private:
  double clear_height_;
};

class ButtonPressScriptedPolicy : public FrontButtonScriptedPolicy {};

class ButtonPressWallScriptedPolicy : public FrontButtonScriptedPolicy {
 public:
  ButtonPressWallScriptedPolicy() : FrontButtonScriptedPolicy(0.25) {}
};

// button-press-topdown's policy: it rises over the wall on its way.
class ButtonPressTopdownWallScriptedPolicy : public ButtonPressTopdownScriptedPolicy {};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_BUTTON_BUTTONS_H_
