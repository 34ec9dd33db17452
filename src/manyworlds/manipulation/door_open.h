// door-open: swing a door open by its handle, toward the robot, until the
// handle is within 0.08 m of the goal in x (metaworld.md §2.9).
//   door anchor obj_pos in [(0, 0.85, 0.15), (0.1, 0.95, 0.15)] (layout in
//     door_fixture.h); goal = obj_pos + (-0.3, -0.45, 0), so in
//     [(-0.3, 0.4, 0.15), (-0.2, 0.5, 0.15)]; hand starts at (0, 0.6, 0.2)
//   reach = tol(|tcp - handle|, (0, 0.02), margin |tcp_init - handle_init|)
//   engaged = H(reach, grip effort (a[3] + 1) / 2)
//   in_place = tol(|handle_x - goal_x|, (0, 0.08),
//                  margin |handle_init_x - goal_x|)
//   reward = 2 engaged + 8 in_place; 10 on success
//   info: success |handle_x - goal_x| <= 0.08; near_object |tcp - handle|
//     <= 0.03; grasp_success = a pad touches the handle and a[3] > 0;
//     grasp_reward = engaged; in_place_reward; obj_to_target =
//     |handle_x - goal_x|.
#ifndef MANYWORLDS_MANIPULATION_DOOR_OPEN_H_
#define MANYWORLDS_MANIPULATION_DOOR_OPEN_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class DoorOpen : public ArticulatedTask {
 public:
  explicit DoorOpen(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Grasps the handle's grip and carries it around the hinge (found from the
// goal) until the door is open past the goal.
class DoorOpenScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DOOR_OPEN_H_
