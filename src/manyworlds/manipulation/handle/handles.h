// The handle tasks of the press family (Meta-World v3, reward version
// "v2"): a handle on a vertical slide (assets/handle_press.xml, turned a
// quarter turn for the "side" tasks, handle_press_side.xml), 0.1 m of
// travel (v3's joint range); hand starts at (0, 0.6, 0.2) (press tasks:
// 2.5 cm higher, see handles.cc); obs[7:11] zeros. The observation bounds
// the goal by v3's goal_space: the hand's bounds for the side tasks,
// (-0.1, 0.55, 0.04)-(0.1, 0.7, 0.08) (handle-press) and (-0.1, 0.55, 0.04)-
// (0.1, 0.7, 0.18) (handle-pull), wider than where the goals lie.
//
// handle-press, handle-press-side: press the handle down from the top.
//   post obj_pos in [(-0.1, 0.8, -0.001), (0.1, 0.9, 0.001)] (handle-press)
//     or [(-0.35, 0.65, -0.001), (-0.25, 0.75, 0.001)] (-side); the object
//     point is the top of the bar's middle, obj_pos + (0, -0.216, 0.171)
//     (-side: (0.216, 0, 0.171)) at reset; goal obj_pos + (0, -0.216, 0.075)
//     (-side: (0.216, 0, 0.075)).
//   d = |obj_z - goal_z|; in_place = tol(d, (0, 0.02), margin
//     |d at reset - 0.02|); reach = tol(|obj - tcp|, (0, 0.02), margin
//     | |handle_init - tcp_init| - 0.02 |); reward = 10 H(reach, in_place),
//     10 once d <= 0.02.
//   info: success d <= 0.02 (a press of 7.6 cm); near_object
//     |obj - tcp| <= 0.05; grasp_success 1; grasp_reward reach;
//     in_place_reward in_place; obj_to_target d.
//
// handle-pull, handle-pull-side: pull the handle up from the bottom.
//   post obj_pos in [(-0.1, 0.8, -0.001), (0.1, 0.9, 0.001)] (handle-pull)
//     or [(-0.35, 0.65, 0), (-0.25, 0.75, 0)] (-side); the handle starts at
//     the bottom of its travel; goal obj_pos + (0, -0.216, 0.172) (-side:
//     (0.216, 0, 0.172)). The object point: handle-pull, 5 cm along the bar
//     from its middle and 1.4 cm above its axis (obj_pos + (0.05, -0.216,
//     0.064) at reset); handle-pull-side, on the arm 4.6 cm from the bar's
//     axis at the arm's height (obj_pos + (0.17, 0, 0.05) at reset), and
//     obj_init is that point at reset.
//   d = |obj_z - goal_z| (handle-pull) or |obj - goal| (-side);
//     in_place = tol(d, (0, 0.05), margin d from obj_init);
//     g = the shared caging of obj (radius 0.022, pad threshold 0.05; -side
//     0.032, 0.06; reach radius 0.01, xz 0.01, high density);
//     reward = H(g, in_place), + 1 + 5 in_place with the tcp within 0.035 of
//     obj and obs[3] > 0 (v3 also compares obj_y - 0.01 with obj_init_z in
//     handle-pull, always true, and obj_z - 0.01 in -side); 10 once d < 0.05.
//   info: success d <= 0.05 (handle-pull: a pull of 5.8 cm) or <= 0.08
//     (-side: 5.7 cm); grasp_success obs[3] > 0 and obj_z - 0.03 >
//     obj_init_z; near_object |obj - tcp| <= 0.05; grasp_reward g.
//   (tol: long-tail tolerance; H: Hamacher product.)
//   v1 (all four): reward = -|left finger - obj| + max(progress(|obj.z -
//     goal.z|), 0) within 5 cm, max_dist = that height difference at reset
//     (maxDist; handle-pull's reads the handle site's height in its body's
//     frame, 0.022 in v3's model, kept as v3 has it); info from v1's zeros:
//     success <= 0.02 (press), 0.05 (handle-pull), 0.08 (handle-pull-side);
//     near_object 1; grasp_success 1 (press) or 0 (pull).
#ifndef MANYWORLDS_MANIPULATION_HANDLE_HANDLES_H_
#define MANYWORLDS_MANIPULATION_HANDLE_HANDLES_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

// The press tasks' handle springs back up (stiffness 150 N/m, 1.5 N at the
// top of its travel, 16.5 N at the bottom), so only a held press counts
// (v3's stays where it is pushed, and its random policy presses it in 12 of
// 50 episodes, measured); the pull tasks' handle stays where it is left.
class HandlePressTask : public ArticulatedTask {
 protected:
  HandlePressTask(SawyerTaskConfig config, FixtureSpec fixture, SawyerOptions options);
  void PlaceObjects(mjModel* m, mjData* d) override;
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;

 private:
  int joint_ = -1, qpos_ = -1;
};

class HandlePress : public HandlePressTask {
 public:
  explicit HandlePress(SawyerOptions options = {});
  static SawyerTaskConfig Config();
};

class HandlePressSide : public HandlePressTask {
 public:
  explicit HandlePressSide(SawyerOptions options = {});
  static SawyerTaskConfig Config();
};

class HandlePull : public ArticulatedTask {
 public:
  explicit HandlePull(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

class HandlePullSide : public ArticulatedTask {
 public:
  explicit HandlePullSide(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Rises over the handle, lines the closed fingers up above the object point
// (the bar's top) and presses straight down.
class HandlePressScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

// Grasps the handle at the object point + `grasp_offset` (the bar under
// handle-pull's point; handle-pull-side's point on the arm itself), holds
// it closed for a few steps and lifts it.
class HandlePullScriptedPolicy : public Policy {
 public:
  explicit HandlePullScriptedPolicy(Vec3 grasp_offset = {0.0, 0.0, -0.014})
      : grasp_offset_(grasp_offset) {}
  void BeginEpisode() override { closed_steps_ = 0; }
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;

 private:
  Vec3 grasp_offset_;
  int closed_steps_ = 0;
};

class HandlePullSideScriptedPolicy : public HandlePullScriptedPolicy {
 public:
  HandlePullSideScriptedPolicy() : HandlePullScriptedPolicy({0.0, 0.0, 0.0}) {}
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_HANDLE_HANDLES_H_
