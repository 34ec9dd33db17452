// The coffee family (Meta-World v3, reward version "v2"): a coffee machine
// with a button on its front and a mug (coffee-button, coffee-push,
// coffee-pull). Shared here: where the mug stands relative to the machine
// and how it is put down at reset. The machine's housing is
// assets/coffee_machine.xml, the mug assets/coffee_mug.xml.
#ifndef MANYWORLDS_MANIPULATION_COFFEE_COFFEE_H_
#define MANYWORLDS_MANIPULATION_COFFEE_COFFEE_H_

#include <mujoco/mujoco.h>

#include "manyworlds/manipulation/reward_utils.h"

namespace manyworlds::manipulation::coffee {

// The mug's place at the machine, this far in front of (-y) the machine's
// origin (v3's site coffee_goal, 3.5 cm in front of the spout): v3 puts its
// mug there in coffee-button, the goal there in coffee-push, the mug's
// start there in coffee-pull.
inline constexpr double kMugBeforeMachine = 0.22;

// Puts the mug (free joint at qpos/dof addresses `qpos`, `dof`) at rest on
// the table with its foot at (x, y): at the height and yaw v3's mug has
// there. v3 sets only the mug's position at reset, at the drawn height
// (-0.001..0.001 m), leaving the orientation its fall from the model's start
// during the hand's settling gave it, a yaw of -3.42 deg and a tilt of
// 0.3 deg; within 5 steps it settles, its foot 2.8-2.9 mm below the table
// top (measured in the official package). Ours starts at rest there,
// level, with that yaw; obs[7:11] thus starts at v3's (x, y, z, w) but for
// the tilt.
void PlaceMug(mjData* d, int qpos, int dof, double x, double y);

}  // namespace manyworlds::manipulation::coffee

#endif  // MANYWORLDS_MANIPULATION_COFFEE_COFFEE_H_
