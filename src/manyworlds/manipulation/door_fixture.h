// Geometry of the door in assets/door_fixture.xml, shared by door-open and
// door-close; the numbers must match the XML.
//
// obj_pos is the door's anchor at handle height, as in Meta-World: the
// reference goals (door-open obj + (-0.3, -0.45, 0), door-close
// obj + (0.2, -0.2, 0)) fix the layout. The closed handle sits exactly on
// door-close's goal; door-open's goal is where the handle would be with the
// door swung open a little past 90 degrees, and success only asks for the
// handle's x (within 0.08), as in the reference.
#ifndef MANYWORLDS_MANIPULATION_DOOR_FIXTURE_H_
#define MANYWORLDS_MANIPULATION_DOOR_FIXTURE_H_

#include <cmath>

#include "manyworlds/manipulation/reward_utils.h"

namespace manyworlds::manipulation::door {

// Root body "door_frame" (on the table, under the hinge) relative to obj_pos.
inline constexpr Vec3 kFrameOffset{-0.1, -0.11, -0.15};
// The handle relative to the hinge axis with the door closed: 0.3 m along
// the panel, 0.09 m in front of it.
inline constexpr double kHandleAlong = 0.3;
inline constexpr double kHandleOut = 0.09;
// The hinge turns from 0 (closed) to -2.1 rad (open, toward the robot).
inline constexpr double kMaxOpen = 2.1;

// Where the hinge axis is for a given obj_pos (z: unchanged).
inline Vec3 Hinge(const Vec3& obj) {
  return {obj[0] + kFrameOffset[0], obj[1] + kFrameOffset[1], obj[2]};
}
// The handle's angle about the hinge (atan2 of its xy offset) when closed.
inline double ClosedHandleAngle() { return std::atan2(-kHandleOut, kHandleAlong); }

}  // namespace manyworlds::manipulation::door

#endif  // MANYWORLDS_MANIPULATION_DOOR_FIXTURE_H_
