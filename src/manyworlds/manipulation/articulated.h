// The articulated-fixture family: tasks whose object is a handle or button
// on a fixture with one joint (door, drawer, window, button, lever). Shared
// here: placing the fixture, the goal fixed relative to it, the record's
// fixture fields, and the scripted-policy moves. Each task computes
// Meta-World v3's own reward (reward_function_version "v2").
//
// The task state keeps the suite's {"obj_pos", "goal_pos"}: obj_pos places
// the fixture at the point Meta-World's does, goal_pos = obj_pos + the
// task's fixed offset (Meta-World's _target_pos relative to that point), so
// the goal range is the object range shifted by that offset and a goal that
// is not its own offset is rejected. The origin of body "obj" is the
// object point of obs[4:7], placed on the handle where Meta-World's task
// reads its own (a handle geom's centre, a site, or a fixed offset from the
// moving part).
#ifndef MANYWORLDS_MANIPULATION_ARTICULATED_H_
#define MANYWORLDS_MANIPULATION_ARTICULATED_H_

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "manyworlds/manipulation/policy_utils.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

// Where a task's fixture goes and how it starts.
struct FixtureSpec {
  std::string root_body;  // placed at obj_pos + root_offset at every reset
  Vec3 root_offset{};
  std::string joint;      // the fixture's joint
  double joint_init = 0;  // its position at reset
  Vec3 goal_offset{};     // goal = obj_pos + goal_offset
  // The record's joint_qpos = this times the joint's position (Meta-World's
  // sign convention); 0: the task records none.
  double joint_qpos_sign = 0;
  // Moves body "obj"'s origin by this (in its parent's frame) and leaves its
  // geoms and mass where they are: for a task that shares a fixture model
  // but reads another point of the handle (drawer-close).
  Vec3 obj_origin_shift{};
  // obj_init = the object point at reset (Meta-World's drawer-close), not
  // obj_pos.
  bool obj_init_is_object_point = false;
};

// Sets the goal range to the object range shifted by `goal_offset` and
// drops the object-goal separation rule (the goal comes from the object).
void UseGoalOffset(const Vec3& goal_offset, SawyerTaskConfig& config);

class ArticulatedTask : public SawyerTask {
 protected:
  ArticulatedTask(SawyerTaskConfig config, FixtureSpec fixture, SawyerOptions options);

  Vec3 DeriveGoal(const Vec3& obj, const Vec3& drawn_goal) const override;
  // Moves the fixture's root body (and body "obj"'s origin, with
  // obj_origin_shift) and sets its joint to the start position.
  void PlaceObjects(mjModel* m, mjData* d) override;
  // joint_qpos.
  void RefreshTaskState(const mjData* d, SawyerState& state) const override;
  // handle_init = the object point at reset; obj_init with
  // obj_init_is_object_point.
  void InitTaskState(SawyerState& state) const override;

 private:
  FixtureSpec fixture_;
  int root_body_ = -1, joint_qpos_ = -1, joint_dof_ = -1;
  int obj_body_ = -1;
  // Body "obj"'s origin, inertial offset and geom offsets in the model file.
  Vec3 obj_pos0_{}, obj_ipos0_{};
  std::vector<std::pair<int, Vec3>> obj_geom_pos0_;
};

// ---- Reward pieces ----

// Gripper closing effort in [0, 1]: (clip(a[3], -1, 1) + 1) / 2.
double GripEffort(std::span<const float> action);

// The reward and info of the press and push tasks (buttons, door-lock,
// door-unlock), which PressRewardTerms builds.
struct PressReward {
  double reward = 0;          // the shaped reward
  double obj_to_target = 0;   // info obj_to_target
  double success_radius = 0;  // success: obj_to_target within it
  double tcp_to_obj = 0;      // near_object: within 5 cm
  double near = 0;            // info grasp_reward
  double pressed = 0;         // info in_place_reward
};
// grasp_success: the gripper is not shut.
RewardTerms PressRewardTerms(const SawyerState& state, const PressReward& parts);

// The reward and info of the tasks that reach the handle and move it
// (dial-turn, window-open/close, drawer-close, handle-press), which
// ReachAndMoveTerms builds: reward 10 H(reach, in_place), or 10 on success
// where ten_at_success; grasp_success 1.
struct ReachAndMove {
  double reach = 0;          // info grasp_reward
  double in_place = 0;       // info in_place_reward
  double obj_to_target = 0;  // info obj_to_target
  bool success = false;
  bool near = false;  // info near_object
  bool ten_at_success = false;
};
RewardTerms ReachAndMoveTerms(const ReachAndMove& parts);

// ---- Scripted-policy moves (stateless functions of the observation) ----

// Grasps a handle at `grasp` with the tcp and then moves the grasp point
// toward `move_to`. Phases, chosen from the observation each step:
//  1. holding (tcp at the grasp point, gripper closed on it): move, closed,
//     at most `carry_speed` action units per axis (slower moves need less
//     friction from the pads where the handle slides along them);
//  2. not above the grasp point: go there `approach_height` up, opening
//     the gripper to `approach_grip` (-1 fully open; more closed where the
//     fixture leaves little room beside the handle);
//  3. above it: descend; 4. at it: close.
void GraspAndMove(const SawyerObs& obs, const Vec3& grasp, const Vec3& move_to,
                  double approach_grip, std::span<float> action, double carry_speed = 1.0,
                  double approach_height = 0.08);

// Rotation of point p by `angle` (right hand) about the line through
// `center` along world axis `axis` (0 = x, 1 = y, 2 = z).
Vec3 TurnAbout(const Vec3& p, const Vec3& center, int axis, double angle);
// The angle of p about that line: atan2 of its two other coordinates
// (relative to center) in cyclic order (z axis: atan2(y, x); x axis:
// atan2(z, y)).
double AngleAbout(const Vec3& p, const Vec3& center, int axis);

// For a handle held and turned about a hinge: where to move the grasp point
// next to turn it toward `target_angle`, at most `max_step` radians ahead.
Vec3 NextPointOnArc(const Vec3& grasp, const Vec3& center, int axis, double target_angle,
                    double max_step = 0.15);

// Turns a panel hinged on a vertical axis through `hinge` (a door) toward
// `target_angle` by pushing one of its faces with the closed gripper.
// Angles are the panel's direction from the hinge, atan2 in the xy plane;
// the pushed face is the one the panel turns away from. The tcp stays at
// `height` and `push_at` metres out from the hinge along the panel. From the
// other side it goes over the panel (above `clear_height`), comes down
// beside the face, then pushes toward where the panel will be a little
// further on.
void PushPanel(const SawyerObs& obs, const Vec3& hinge, double angle, double target_angle,
               double push_at, double height, double clear_height, std::span<float> action);

// Pushes a vertical handle bar along x to `target_x` with the side of one
// open finger pad (the other pad and the palm stay in front of the fixture,
// which lies behind the bar in +y): line the +y pad up with the bar on the
// side away from the target, at bar height, then sweep it toward target_x.
void PushBarAlongX(const SawyerObs& obs, const Vec3& bar, double target_x, std::span<float> action);

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_ARTICULATED_H_
