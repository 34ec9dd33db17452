// shelf-place: pick up the block and put it on the shelf of a bookcase (a
// cabinet below the shelf, an open compartment above it).
//   block (4 cm cube) in [(-0.1, 0.5, 0.02), (0.1, 0.6, 0.02)]
//   goal (the block's centre resting on the shelf; bookcase foot = goal -
//     (0, 0, 0.3)) in [(-0.1, 0.8, 0.3), (0.1, 0.9, 0.3)]; the shelf is
//     8 cm deep in front of the goal, so within 7 cm of the goal the block
//     is over the shelf
//   in_place = tol(|obj - goal|, (0, 0.05), margin |obj_init - goal|),
//     less H(depth, under) while the block is below the shelf top (depth =
//     how far, as a fraction of the shelf height) and within 15 cm in front
//     of the goal (under = how close in y), where the shelf blocks it
//   grasped = gripper caging (high density; obj radius 0.02, pad 0.05,
//     xz 0.01)
//   reward = H(grasped, in_place); + 1 + 5 in_place while held (tcp within
//     2.5 cm, opening > 0, lifted 1 cm); 10 once |obj - goal| < 0.05
//   info: success |obj - goal| <= 0.07; near_object |tcp - obj| <= 0.03;
//     grasp_success = touching, opening > 0 and lifted 2 cm;
//     grasp_reward = grasped; in_place_reward; obj_to_target = |obj - goal|.
//   v1: as pick-place's (v1::PickPlace, lift target 0.04 m above the
//     object's start); info from v1's zeros: success |obj - goal| <= 0.07,
//     near_object 1, grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_PICK_PLACE_SHELF_PLACE_H_
#define MANYWORLDS_MANIPULATION_PICK_PLACE_SHELF_PLACE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/object_tasks.h"

namespace manyworlds::manipulation {

class ShelfPlace : public GoalFixtureTask {
 public:
  explicit ShelfPlace(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the block, lifts it above the shelf's height in front of the
// bookcase, then slides it in over the shelf to the goal.
class ShelfPlaceScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PICK_PLACE_SHELF_PLACE_H_
