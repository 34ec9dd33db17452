// pick-place-wall (Meta-World v3): carry the puck over a wall to a goal in
// the air behind it.
//   goal in (-0.05, 0.85, 0.05)-(0.05, 0.9, 0.3)
//   reward (v3): g = caging (not high density; radius 0.015, pads 0.05, xz
//     0.005); first toward the midpoint (goal x, 0.77, 0.25) over the wall,
//     z counting three times: H(g, m); held (tcp within 2 cm, not shut,
//     lifted 1.5 cm) H(g, m) + 1 + 4 m, and once past y 0.75
//     H(g, m) + 5 + 3 tol(|puck - goal|, (0, 0.05)); 10 within 0.05.
//   info: success |puck - goal| <= 0.07; in_place_reward = the goal term.
//   v1: as pick-place's (v1::PickPlace, lift target 0.04 m above the
//     object's start); info from v1's zeros: success |obj - goal| <= 0.07,
//     near_object 1, grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_PICK_PLACE_PICK_PLACE_WALL_H_
#define MANYWORLDS_MANIPULATION_PICK_PLACE_PICK_PLACE_WALL_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class PickPlaceWall : public SawyerTask {
 public:
  explicit PickPlaceWall(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the puck, lifts it over the wall, carries it to the goal.
class PickPlaceWallScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PICK_PLACE_PICK_PLACE_WALL_H_
