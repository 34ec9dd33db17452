// The rotary family: a knob or handle that turns about a vertical axis
// (faucet-open, faucet-close, dial-turn; Meta-World v3, reward version
// "v2"). The fixtures are ArticulatedTask fixtures with a hinge about z;
// shared here is the scripted move that turns them: push a bar that points
// out from the axis sideways with the closed gripper, following it round.
#ifndef MANYWORLDS_MANIPULATION_BAR_PUSH_H_
#define MANYWORLDS_MANIPULATION_BAR_PUSH_H_

#include <span>

#include "manyworlds/manipulation/policy_utils.h"
#include "manyworlds/manipulation/reward_utils.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation::rotary {

// A bar turning about the axis through `center` along world axis `depth`
// (2: a vertical axis, a knob on a table; 1: an axis along y, a lock on a
// door), pointing at angle `bar_angle` in the plane of the two other axes
// (atan2 of its (a, b) coordinates, a and b in cyclic order after depth:
// (x, y) for z, (z, x) for y), from the axis toward the bar's end.
// `direction` +1 turns it toward larger angles, -1 toward smaller. The tcp
// pushes the bar's trailing side `push_at` metres out from the axis, with
// its `depth` coordinate at `height`: it lines up `standoff` metres behind
// the bar, `clear` metres off along depth (+: above a knob; -: in front of
// a lock, toward the robot), comes in, and then keeps pushing a few
// centimetres ahead of the bar as the bar turns. The gripper stays closed.
struct BarPush {
  Vec3 center;
  double bar_angle = 0;
  int direction = 1;
  double push_at = 0.1;
  double height = 0.1;
  double standoff = 0.035;
  int depth = 2;
  double clear = 0.06;
};
void PushBarAround(const SawyerObs& obs, const BarPush& push, std::span<float> action);

}  // namespace manyworlds::manipulation::rotary

#endif  // MANYWORLDS_MANIPULATION_BAR_PUSH_H_
