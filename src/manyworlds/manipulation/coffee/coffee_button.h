// coffee-button (Meta-World v3, reward version "v2"): push the coffee
// machine's button in (+y).
//   machine obj_pos in [(-0.1, 0.8, -0.001), (0.1, 0.9, 0.001)] (v3's
//     coffee_machine body); the button's face (obs[4:7], v3's site
//     buttonStart) rests at obj_pos + (0, -0.22, 0.3) and goes in by up to
//     0.03 m; goal = obj_pos + (0, -0.19, 0.3), the full press; the mug
//     stands at the machine, at obj_pos + (0, -0.22, 0) (coffee.h); hand
//     starts at (0, 0.4, 0.2), bounds (-0.5, 0.4, 0.05)-(0.5, 1, 0.5);
//     obs[7:11] = (1, 0, 0, 0), as v3 writes (the machine's (w, x, y, z)).
//   reward: button-press's (press/buttons.h) with v3's press margin
//     max_dist = 0.03 (record obj_to_target_init): obj_to_target =
//     |goal_y - button_y|; pressed = tol(obj_to_target, (0, 0.005), 0.03);
//     near = tol(|button - tcp|, (0, 0.05), margin |button - tcp_init|);
//     2 H(max(obs[3], 0), near), + 8 pressed with |button - tcp| <= 0.05.
//   info: success obj_to_target <= 0.02 (a press of 1 cm); near_object
//     |button - tcp| <= 0.05; grasp_success obs[3] > 0; grasp_reward near;
//     in_place_reward pressed.
//   (tol: long-tail tolerance; H: Hamacher product.)
// Our machine's frame round the button has its top bar set back (see
// assets/coffee_machine.xml) so that our fingers press the button with the
// tcp as close to it as v3's: 1.5 cm in front of its face.
//   v1: button-press's (FrontButtonRewardV1: the left finger's reach, the
//     press depth's progress bonus; max_dist = |obj.y - goal.y| at reset,
//     v3's maxDist); info from v1's zeros: success <= 0.02, near_object 1.
#ifndef MANYWORLDS_MANIPULATION_COFFEE_COFFEE_BUTTON_H_
#define MANYWORLDS_MANIPULATION_COFFEE_COFFEE_BUTTON_H_

#include "manyworlds/manipulation/articulated.h"
#include "manyworlds/manipulation/button/buttons.h"

namespace manyworlds::manipulation {

class CoffeeButton : public ArticulatedTask {
 public:
  explicit CoffeeButton(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  // The machine, then the mug in front of it.
  void PlaceObjects(mjModel* m, mjData* d) override;
  // Also obj_to_target_init = v3's max_dist.
  void InitTaskState(SawyerState& state) const override;

 private:
  int mug_qpos_ = -1, mug_dof_ = -1;
};

// button-press's: the closed fingers line up in front of the button and
// push it to its stop.
class CoffeeButtonScriptedPolicy : public FrontButtonScriptedPolicy {};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_COFFEE_COFFEE_BUTTON_H_
