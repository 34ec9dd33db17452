// The drawer family: a cabinet at obj_pos in [(-0.1, 0.9, 0), (0.1, 0.9, 0)]
// whose drawer slides along y (assets/drawer_fixture.xml); hand starts at
// (0, 0.6, 0.2). DrawerTask holds what both tasks share (the ranges, v1's
// reward); each computes Meta-World v3's own reward (version "v2").
//
// drawer-open: pull a drawer out of its cabinet by the handle until the
// object point is within 0.03 m of the goal.
//   the object point (obs[4:7]) is 1 cm in front of the handle bar's
//     centre, at obj_pos + (0, -0.17, 0.09) when shut; goal = obj_pos +
//     (0, -0.36, 0.09) (v3: the point pulled out 0.2 m minus 1 cm), so
//     success needs the drawer pulled out >= 0.16 m of its 0.2 m; obs[7:11]
//     the handle's (w, x, y, z) orientation
//   opening = tol(|handle - goal|, (0, 0.02), margin 0.2)
//   caging = tol(|(handle - hand) * (3, 3, 1)|, (0, 0.01),
//     margin |(goal + (0, 0.2, 0) - tcp_init) * (3, 3, 1)|) (hand = obs[0:3])
//   reward = 5 (caging + opening) (at most 10; no success bonus)
//   info: success |handle - goal| <= 0.03; near_object |handle - hand|
//     <= 0.03; grasp_success = obs[3] > 0; grasp_reward = caging;
//     in_place_reward = opening; obj_to_target = |handle - goal|.
//   (tol: long-tail tolerance.)
//   v1: reward = -|tcp - obj| + (|tcp - obj| < 0.05 ? max(progress(|obj.y -
//     goal.y|), 0) : 0), max_dist 0.2 (maxDist); info from v1's zeros:
//     success |obj.y - goal.y| <= 0.03, near_object 1, grasp_success 0.
//
// drawer-close: push an open drawer shut until the object point is within
// 0.065 m of the goal.
//   the drawer starts pulled out 0.15 m; the object point (obs[4:7]) is
//     1 cm in front of and 5 cm above the handle bar's centre, as v3's, so
//     it is 0.051 m from the goal even when shut; goal = the shut bar =
//     obj_pos + (0, -0.16, 0.09), so success needs the drawer pushed to
//     within 0.0315 m of shut; obs[7:11] zeros (as v3)
//   in_place = tol(|handle - goal|, (0, 0.05),
//     margin ||obj_init - goal| - 0.05|) (obj_init = the point at reset)
//   reach = H(tolG(|handle - tcp|, (0, 0.005),
//     margin ||obj_init - tcp_init| - 0.005|), clip(a[3], 0, 1))
//   reward = 10 H(reach, in_place); 10 on success
//   info: success |handle - goal| <= 0.065; near_object |handle - tcp|
//     <= 0.01; grasp_success 1 (as v3); grasp_reward = reach;
//     in_place_reward = in_place; obj_to_target = |handle - goal|.
//   (tol: long-tail, tolG: gaussian tolerance; H: Hamacher product.)
//   v1: reward = -|tcp - obj| + (|tcp - obj| < 0.05 ? max(progress(|obj.y -
//     goal.y|), 0) : 0), max_dist 0.15 (maxDist); info from v1's zeros:
//     success |obj.y - goal.y| <= 0.065, near_object 1, grasp_success 1.
#ifndef MANYWORLDS_MANIPULATION_DRAWER_DRAWER_H_
#define MANYWORLDS_MANIPULATION_DRAWER_DRAWER_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

// The v1 values that tell the two drawer tasks apart.
struct DrawerV1 {
  double success;        // |obj.y - goal.y| within this
  double max_dist;       // v3's maxDist
  double grasp_success;  // v3's info value
};

class DrawerTask : public ArticulatedTask {
 protected:
  DrawerTask(SawyerTaskConfig config, FixtureSpec fixture, DrawerV1 v1, SawyerOptions options);
  // The cabinet's ranges and the hand's start, with the task's names and
  // goal offset.
  static SawyerTaskConfig DrawerConfig(const char* id, const char* description,
                                       const char* xml_file, QuatLayout obj_quat,
                                       const Vec3& goal_offset);
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;

 private:
  DrawerV1 v1_;
};

class DrawerOpen : public DrawerTask {
 public:
  explicit DrawerOpen(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

class DrawerClose : public DrawerTask {
 public:
  explicit DrawerClose(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Grasps the handle bar (gripper half open on the way down: the drawer face
// is close behind the bar) and pulls it out to the drawer's stop.
class DrawerOpenScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

// Comes down in front of the handle with the gripper closed and pushes it
// in.
class DrawerCloseScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DRAWER_DRAWER_H_
