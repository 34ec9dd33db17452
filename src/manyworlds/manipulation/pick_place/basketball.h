// basketball: pick up the ball and put it through the hoop.
//   ball (radius 3 cm) in [(-0.1, 0.6, 0.03), (0.1, 0.7, 0.03)]
//   hoop stand in [(-0.1, 0.85, 0), (0.1, 0.9, 0)]; the goal is the ring's
//     centre, stand + (0, -0.083, 0.25), so goal_pos lies in
//     [(-0.1, 0.767, 0.25), (0.1, 0.817, 0.25)] (v3's); the observation
//     bounds it by v3's goal_space, that box with z widened 0.1 mm either
//     way. obs[7:11] the ball's (w, x, y, z), as v3's.
//   in_place = tol(|W (obj - goal)|, (0, 0.08), margin |W (obj_init - goal)|)
//     with W = (1, 1, 2): height counts double
//   grasped = gripper caging (high density; obj radius 0.025, pad 0.06,
//     xz 0.005), 1 while held (tcp within 3.5 cm, opening > 0, lifted 1 cm)
//   reward = H(grasped, in_place); + 1 + 5 in_place while held; 10 once
//     |obj - goal| <= 0.08
//   info: success |obj - goal| <= 0.08; near_object |tcp - obj| <= 0.03;
//     grasp_success = touching, opening > 0 and lifted 2 cm;
//     grasp_reward = grasped; in_place_reward; obj_to_target = |obj - goal|.
//   v1: as pick-place's (v1::PickPlace, lift target 0.3 m above the
//     object's start); info from v1's zeros: success |obj - goal| <= 0.08,
//     near_object 1, grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_PICK_PLACE_BASKETBALL_H_
#define MANYWORLDS_MANIPULATION_PICK_PLACE_BASKETBALL_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/object_tasks.h"

namespace manyworlds::manipulation {

class Basketball : public GoalFixtureTask {
 public:
  explicit Basketball(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the ball, lifts it straight up above the ring's height, carries it
// over the ring and lowers it through into the net.
class BasketballScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PICK_PLACE_BASKETBALL_H_
