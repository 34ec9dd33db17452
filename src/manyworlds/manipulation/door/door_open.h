// door-open: swing a door open by its handle, toward the robot, until the
// handle is within 0.08 m of the goal in x (Meta-World v3, reward version
// "v2").
//   door anchor obj_pos in [(0, 0.85, 0.15), (0.1, 0.95, 0.15)] (layout in
//     door_fixture.h); goal = obj_pos + (-0.3, -0.45, 0), so in
//     [(-0.3, 0.4, 0.15), (-0.2, 0.5, 0.15)]; hand starts at (0, 0.6, 0.2);
//     obs[4:7] the handle's centre, obs[7:11] its (x, y, z, w) orientation
//   With h = obs hand, p = handle + (-0.05, 0, 0), r = |h_xy - p_xy|:
//   floor = 0 if r <= 0.12, else 0.04 ln(r - 0.12) + 0.4
//   above_floor = 1 if h_z >= floor, else tol(floor - h_z, (0, 0.01),
//     margin floor / 2)
//   in_place = tol(|h - handle - (0, 0.03, -0.01)|, (0, 0.06), margin 0.5)
//   ready = H(above_floor, in_place); grab = (clip(a[3]) + 1) / 2
//   opened = 0.2 [theta < -pi/90] + 0.8 tol(2pi/3 + theta, (0, 0.5),
//     margin pi/3), theta = the hinge angle (record joint_qpos, <= 0)
//   reward = 2 H(ready, grab) + 8 opened; 10 on success
//   info: success |handle_x - goal_x| <= 0.08; near_object = ready (a
//     value in [0, 1]); grasp_success = grab >= 0.5; grasp_reward = grab;
//     in_place_reward = opened; obj_to_target = 0 (as v3 reports it).
//   (tol: long-tail tolerance; H: Hamacher product.)
//   v1: reward = -|tcp - obj| + (|tcp - obj| < 0.05 ? max(progress(xy
//     distance to the goal), 0) : 0), max_dist = the handle's xy distance
//     to the goal at reset (maxPullDist); info from v1's zeros: success as
//     v2, every other field 0.
#ifndef MANYWORLDS_MANIPULATION_DOOR_DOOR_OPEN_H_
#define MANYWORLDS_MANIPULATION_DOOR_DOOR_OPEN_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class DoorOpen : public ArticulatedTask {
 public:
  explicit DoorOpen(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Pushes the door open from behind with the closed gripper (PushPanel),
// 0.25 m out from the hinge (found from the goal): over the door, down
// behind it, then around with it. A grip on the handle cannot carry it past
// 90 degrees where the handle's path leaves the hand's bounds (y >= 0.4),
// which it does for the doors nearest the robot.
class DoorOpenScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DOOR_DOOR_OPEN_H_
