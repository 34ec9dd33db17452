// door-close: swing an open door shut, until the handle is within 0.08 m
// of the goal (Meta-World v3, reward version "v2").
//   door anchor obj_pos in [(0, 0.85, 0.15), (0.1, 0.95, 0.15)] (door-open's
//     range; layout in door_fixture.h); the door starts open by pi/2;
//     goal = obj_pos + (0.2, -0.2, 0), 0.012 m from the shut handle, so in
//     [(0.2, 0.65, 0.15), (0.3, 0.75, 0.15)]; hand starts at (-0.5, 0.6, 0.2);
//     obs[4:7] the handle's centre
//   in_place = tolG(|handle - goal|, (0, 0.05), margin |obj_init - goal|)
//     (obj_init = obj_pos, the anchor)
//   hand_in_place = tolG(|tcp - goal|, (0, 0.0125),
//     margin |hand_init - handle| + 0.1)
//   reward = 3 hand_in_place + 6 in_place; 10 when |handle - goal| < 0.05
//   info: success |handle - goal| <= 0.08; near_object 0, grasp_success 1,
//     grasp_reward 1 (constants, as in v3); in_place_reward = hand_in_place;
//     obj_to_target = |handle - goal|.
//   (tolG: gaussian tolerance.)
//   v1: reward = -|tcp - obj| + max(progress(xy distance to the goal), 0)
//     within 5 cm, max_dist = that distance at reset (maxPullDist); info from
//     v1's (reward, distance, 0): success <= 0.08, near_object 0,
//     grasp_success 1, grasp_reward 1.
#ifndef MANYWORLDS_MANIPULATION_DOOR_DOOR_CLOSE_H_
#define MANYWORLDS_MANIPULATION_DOOR_DOOR_CLOSE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class DoorClose : public ArticulatedTask {
 public:
  explicit DoorClose(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Pushes the open door shut on its handle side with the closed gripper
// (PushPanel), 0.2 m out from the hinge (found from the goal), inside the
// handle. (The open door's handle is out of the hand's bounds, y >= 0.4,
// for the doors nearest the robot.)
class DoorCloseScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DOOR_DOOR_CLOSE_H_
