// peg-insert-side: grasp a peg lying on the table and push its head into the
// hole in the side of a box.
//   peg centre in [(0, 0.5, 0.02), (0.2, 0.7, 0.02)], lying along x, head
//     (site peg_head) 10 cm toward -x
//   box in [(-0.35, 0.4, 0), (-0.25, 0.7, 0)]; its 6 cm square hole opens
//     toward +x; the goal is on the hole's axis 7.5 cm deep, box + (0, 0,
//     0.13), so goal_pos lies in [(-0.35, 0.4, 0.13), (-0.25, 0.7, 0.13)]
//     and success needs the head inside the hole
//   to_goal = tol(|W (head - goal)|, (0, 0.05), margin |W (head_init - goal)|)
//     with W = (1, 2, 2): lining up with the hole counts double
//   on_axis = tol(yz distance of the head from the hole axis, (0, 0.01),
//     margin 0.1)
//   in_place = H(to_goal, on_axis)
//   grasped = gripper caging of the peg centre (high density; obj radius
//     0.015, pad 0.05, xz 0.005)
//   reward = H(grasped, in_place); + 1 + 5 in_place while held (tcp within
//     3 cm of the centre, opening > 0, lifted 1 cm); 10 once
//     |head - goal| <= 0.07
//   info: success |head - goal| <= 0.07; near_object |tcp - peg| <= 0.03;
//     grasp_success = touching, opening > 0 and lifted 2 cm;
//     grasp_reward = grasped; in_place_reward; obj_to_target = |head - goal|.
//   v1: v1::PickPlace with the tcp's height change weighted 1 and the place
//     bonus reading the head's distance to the goal until it is within 5 cm
//     (lift target = the peg's start height + kV1Lift); info from v1's
//     zeros: success |obj - goal| <= 0.07, near_object 1, grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_PEG_PEG_INSERT_SIDE_H_
#define MANYWORLDS_MANIPULATION_PEG_PEG_INSERT_SIDE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/object_tasks.h"

namespace manyworlds::manipulation {

class PegInsertSide : public GoalFixtureTask {
 public:
  explicit PegInsertSide(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
  void RefreshTaskState(const mjData* d, SawyerState& state) const override;

 private:
  int peg_head_ = -1;   // site
  int peg_grasp_ = -1;  // site: the observed object point
};

// Grasps the peg at its middle, lifts it onto the hole's axis in front of
// the box, then pushes the head in. Steers by the head, computed from the
// peg's observed pose, so a tilt in the grip is corrected.
class PegInsertSideScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PEG_PEG_INSERT_SIDE_H_
