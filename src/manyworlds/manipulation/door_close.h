// door-close: swing an open door shut, until the handle is within 0.08 m
// of its closed position (metaworld.md §2.9).
//   door anchor obj_pos in [(0, 0.85, 0.15), (0.1, 0.95, 0.15)] (door-open's
//     range; layout in door_fixture.h); the door starts open by 1.6 rad;
//     goal = the closed handle = obj_pos + (0.2, -0.2, 0), so in
//     [(0.2, 0.65, 0.15), (0.3, 0.75, 0.15)]; hand starts at (-0.5, 0.6, 0.2)
//   reward (MoveHandleReward in articulated.h, radius 0.08):
//     reach = tol(d, (0, 0.02), margin |tcp_init - handle_init|), d = the
//       distance from the handle to the nearest of tcp and pads
//     in_place = tol(|handle - goal|, (0, 0.08), margin |handle_init - goal|)
//     reward = 2 reach + 8 in_place; 10 on success
//   info: success |handle - goal| <= 0.08; near_object d <= 0.03;
//     grasp_success = a pad touches the handle; grasp_reward = reach;
//     in_place_reward; obj_to_target = |handle - goal|.
#ifndef MANYWORLDS_MANIPULATION_DOOR_CLOSE_H_
#define MANYWORLDS_MANIPULATION_DOOR_CLOSE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class DoorClose : public ArticulatedTask {
 public:
  explicit DoorClose(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Grasps the handle's grip and carries it around the hinge (found from the
// goal) until the door is shut.
class DoorCloseScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DOOR_CLOSE_H_
