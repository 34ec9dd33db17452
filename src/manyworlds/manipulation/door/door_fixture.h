// Geometry of the door in assets/door_fixture.xml, shared by door-open and
// door-close; the numbers must match the XML.
//
// obj_pos is the door's anchor at handle height, as in Meta-World v3, and
// the hinge and the handle are where v3's are relative to it (measured in
// the official package): the hinge at obj_pos + (-0.185, -0.1), the closed
// handle's centre at obj_pos + (0.1907, -0.2071), 0.3907 m from the hinge.
// So v3's goals mean the same motions: door-open's success (handle x within
// 0.08 of obj_pos x - 0.3) is a door open between 79 and 104 degrees, and
// door-close's goal (obj_pos + (0.2, -0.2, 0)) lies 0.012 m from the shut
// handle, which is within 0.08 of it once the door is within about 9
// degrees of shut.
#ifndef MANYWORLDS_MANIPULATION_DOOR_DOOR_FIXTURE_H_
#define MANYWORLDS_MANIPULATION_DOOR_DOOR_FIXTURE_H_

#include <cmath>

#include "manyworlds/manipulation/articulated.h"
#include "manyworlds/manipulation/reward_utils.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation::door {

// Root body "door_frame" (on the table, under the hinge) relative to obj_pos.
inline constexpr Vec3 kFrameOffset{-0.185, -0.1, -0.15};
// The handle relative to the hinge axis with the door closed: 0.3757 m
// along the panel, 0.1071 m in front of it.
inline constexpr double kHandleAlong = 0.3757;
inline constexpr double kHandleOut = 0.1071;
// The hinge turns from 0 (closed) to -2 rad (open, toward the robot).
inline constexpr double kMaxOpen = 2.0;

// Where the hinge axis is for a given obj_pos (z: unchanged).
inline Vec3 Hinge(const Vec3& obj) {
  return {obj[0] + kFrameOffset[0], obj[1] + kFrameOffset[1], obj[2]};
}
// The handle's angle about the hinge (atan2 of its xy offset) when closed.
inline double ClosedHandleAngle() { return std::atan2(-kHandleOut, kHandleAlong); }
// The hinge angle (0 shut, negative open) that puts the handle at `handle`.
inline double HingeAngle(const Vec3& handle, const Vec3& obj) {
  const Vec3 hinge = Hinge(obj);
  return std::remainder(
      std::atan2(handle[1] - hinge[1], handle[0] - hinge[0]) - ClosedHandleAngle(),
      2 * 3.14159265358979323846);
}
// The scripted policies push the panel with the closed gripper (PushPanel in
// articulated.h): mid-height (the tcp 0.15 m up, as the handle) and clear of
// the handle; over its top (0.29 m) with the tcp 0.34 m up.
// door-open's and door-close's door: the hinge at `start_angle` at reset,
// the goal at obj_pos + goal_offset, joint_qpos in v3's sign (its
// doorjoint has ours).
inline FixtureSpec HingedDoor(double start_angle, const Vec3& goal_offset) {
  FixtureSpec fixture{"door_frame", kFrameOffset, "door_hinge", start_angle, goal_offset};
  fixture.joint_qpos_sign = 1.0;
  return fixture;
}
// Their config: v3's door range, the goal from `goal_offset`.
inline SawyerTaskConfig DoorConfig(const char* id, const char* description, const char* xml_file,
                                   const Vec3& hand_init, const Vec3& goal_offset) {
  SawyerTaskConfig config =
      TaskConfig(id, description, xml_file, {{0.0, 0.85, 0.15}, {0.1, 0.95, 0.15}});
  config.hand_init = hand_init;
  UseGoalOffset(goal_offset, config);
  return config;
}

inline constexpr double kPushHeight = 0.15;
inline constexpr double kClearHeight = 0.34;

}  // namespace manyworlds::manipulation::door

#endif  // MANYWORLDS_MANIPULATION_DOOR_DOOR_FIXTURE_H_
