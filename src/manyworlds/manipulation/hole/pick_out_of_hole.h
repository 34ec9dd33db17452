// pick-out-of-hole (Meta-World v3, reward version "v2"): lift the puck out
// of the hole to a goal above the table.
//   puck obj_pos (0, 0.75, 0.02) (v3's range is one point); goal in
//     (-0.1, 0.5, 0.15)-(0.1, 0.6, 0.3), >= 0.15 m from the puck in xy;
//     hand starts at (0, 0.6, 0.2), bounds (-0.5, 0.4, -0.05)-(0.5, 1, 0.5)
//     (all as v3)
//   table (assets/pick_out_of_hole.xml, v3's raised top): top at
//     z = 0.054, hole x in [-0.15, 0.15], y in [0.65, 0.95], floor z = 0;
//     the puck rests on the floor
//   obs[4:7] the puck's centre, obs[7:11] its (w, x, y, z) (v3's xquat)
//   floor = 0 within 3 cm of obj_init in xy (tcp), else
//     0.015 ln(r - 0.03) + 0.15; above_floor = 1 when tcp z >= floor, else
//     tol(floor - tcp z, (0, 0.01), margin 0.02)
//   grasped = gripper caging (high density; obj radius 0.015, pad 0.02,
//     reach 0.01, xz 0.03, gripper effort 0.1)
//   in_place = tol(|obj - goal|, (0, 0.02), margin |obj_init - goal|)
//   held = |tcp - obj| < 0.04, opening >= 0.33 and the puck 2 cm above
//     obj_init
//   reward = H(grasped, in_place); + 1 + 5 H(in_place, above_floor) while
//     held; 10 once |obj - goal| < 0.05 (v3 reads the base class's 0.05,
//     not its own 0.02)
//   info: success |obj - goal| <= 0.07; near_object |tcp - obj| <= 0.03;
//     grasp_success held; grasp_reward grasped; in_place_reward in_place;
//     obj_to_target |obj - goal|.
//   Our gripper's opening is about 0.5 closed on the 4 cm puck and 0.2
//   closed on nothing, so opening < 0.33 means what it means in v3: shut
//   without the puck.
//   v1: pick-place's (v1::PickPlace, lift target 0.11 above the start,
//     the lift bonus counted from 2 cm below the start); info from v1's
//     zeros: success |obj - goal| <= 0.07, near_object 1, grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_HOLE_PICK_OUT_OF_HOLE_H_
#define MANYWORLDS_MANIPULATION_HOLE_PICK_OUT_OF_HOLE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class PickOutOfHole : public SawyerTask {
 public:
  explicit PickOutOfHole(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the puck, lifts it straight up out of the hole and carries it to
// the goal.
class PickOutOfHoleScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_HOLE_PICK_OUT_OF_HOLE_H_
