// The articulated-fixture family: tasks whose object is a handle or button
// on a fixture with one joint (door, drawer, window, button, lever). Shared
// here: placing the fixture, the goal fixed relative to it, the shape of the
// reward, and the scripted-policy moves.
//
// The task state keeps the suite's {"obj_pos", "goal_pos"}: obj_pos places
// the fixture (each task says which point of it), goal_pos = obj_pos + the
// task's fixed offset, so the goal range is the object range shifted by that
// offset and a goal that is not its own offset is rejected. Body "obj" is
// the handle, so obs[4:7] is the handle position as in Meta-World.
#ifndef MANYWORLDS_MANIPULATION_ARTICULATED_H_
#define MANYWORLDS_MANIPULATION_ARTICULATED_H_

#include <span>
#include <string>

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
};

// Sets the goal range to the object range shifted by `goal_offset` and
// drops the object-goal separation rule (the goal comes from the object).
void UseGoalOffset(const Vec3& goal_offset, SawyerTaskConfig& config);

class ArticulatedTask : public SawyerTask {
 protected:
  ArticulatedTask(SawyerTaskConfig config, FixtureSpec fixture, SawyerOptions options);

  Vec3 DeriveGoal(const Vec3& obj, const Vec3& drawn_goal) const override;
  // Moves the fixture's root body and sets its joint to the start position.
  void PlaceObjects(mjModel* m, mjData* d) override;
  // Also records the handle's start, which the rewards measure from.
  void DoReset(const ObsView& out) override;

  // The fixture joint's position now.
  double joint_pos() const;
  // The handle ("obj") position at reset.
  const Vec3& handle_init() const { return handle_init_; }

 private:
  FixtureSpec fixture_;
  int root_body_ = -1, joint_qpos_ = -1, joint_dof_ = -1;
  Vec3 handle_init_{};
};

// ---- Reward pieces (metaworld.md §3.1 primitives) ----

// Gripper closing effort in [0, 1]: (clip(a[3], -1, 1) + 1) / 2.
double GripEffort(std::span<const float> action);

// Distance from `point` to the nearest of the tcp and the two pads: pushes
// may use either finger.
double FingerDistance(const SawyerState& state, const Vec3& point);

// The family's reward: 2 engaged + 8 in_place, in [0, 10], and 10 on
// success. `engaged` rewards being at (or holding) the handle, `in_place`
// the handle's progress to the goal; both in [0, 1]. Fills reward, success,
// grasp_reward (= engaged) and in_place_reward; the task fills the rest.
RewardTerms FixtureReward(double engaged, double in_place, bool success);

// The whole reward of tasks that move a handle to a goal by any means
// (pushing or holding), success within `radius`:
//   reach = tol(d, (0, 0.02), margin |tcp_init - handle_init|), d = distance
//     from the handle to the nearest of tcp and pads
//   in_place = tol(|handle - goal|, (0, radius), margin |handle_init - goal|)
//   reward = 2 reach + 8 in_place; 10 when |handle - goal| <= radius
//   near_object = d <= 0.03; grasp_success = a pad touches the handle;
//   grasp_reward = reach; obj_to_target = |handle - goal|.
RewardTerms MoveHandleReward(const SawyerState& state, const Vec3& handle_init, double radius);

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

// Pushes a vertical handle bar along x to `target_x` with the side of one
// open finger pad (the other pad and the palm stay in front of the fixture,
// which lies behind the bar in +y): line the +y pad up with the bar on the
// side away from the target, at bar height, then sweep it toward target_x.
void PushBarAlongX(const SawyerObs& obs, const Vec3& bar, double target_x, std::span<float> action);

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_ARTICULATED_H_
