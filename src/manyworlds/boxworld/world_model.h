// The MuJoCo model of a box world, written with the sim layer's MJCF builder.
//
// Model layout (names the env, the tests and the renderer rely on):
//   floor        plane geom, checker material with 1 m squares
//   wall_{+x,-x,+y,-y}  box geoms, inner faces at +-floor_size / 2
//   agent        body at height agent_radius with joints agent_x, agent_y
//                (slides along the world axes, damping 2.5 N s/m) and
//                agent_yaw (hinge about z, damping 1 N m s); geoms agent
//                (sphere, 1 kg) and agent_nose (a small sphere on its +x
//                side, so heading matters when pushing); it never touches
//                the floor (collision bits), so it glides
//   box<i>       body with a free joint box<i>, one geom box<i> of the box's
//                shape, size, mass, friction and colour
//   target       site: a flat disc of radius success_radius on the floor
//   motors       agent_x, agent_y (ctrl range +-agent_force N, gear 1),
//                agent_yaw (ctrl range +-agent_torque N m)
//   cameras      top (straight down, the whole floor), perspective (from
//                the -y side, 50 degrees down), front (the same as
//                perspective: render's default camera name)
// Physics: timestep 0.005 s; the env applies each action for 5 steps.
// Start positions and the target are not part of the compiled structure:
// the env writes them into qpos at reset and into the target site's
// position (SameStructure tells when a model can be reused).
#ifndef MANYWORLDS_BOXWORLD_WORLD_MODEL_H_
#define MANYWORLDS_BOXWORLD_WORLD_MODEL_H_

#include <string>

#include "manyworlds/boxworld/world.h"
#include "manyworlds/sim/mjcf.h"
#include "manyworlds/sim/model.h"

namespace manyworlds::boxworld {

inline constexpr double kTimestep = 0.005;
inline constexpr int kFrameSkip = 5;
inline constexpr double kAgentMass = 1.0;
inline constexpr double kAgentDamping = 2.5;     // N s/m on x and y
inline constexpr double kWallThickness = 0.1;    // the walls stand outside the floor
inline constexpr double kAgentYawDamping = 1.0;  // N m s about z

// Sizes of the model's contact list (<size nconmax>) and constraint rows
// (njmax): max(100, 50 + 6 x boxes) contacts and 4 rows per contact (a
// pyramidal cone of condim 3), at least 500. MuJoCo 2.2.2's defaults (100
// and 500, kept up to 8 boxes) hold about 25 boxes resting on the floor (4
// contacts each); every step of a world with more raised CONTACTFULL and
// ended the episode. 64 cubes pushed by the scripted policy peak at 273
// contacts of the 434; their mjData's buffer is 53 MB (the constraint
// arrays grow with njmax squared; the default's is 3.2 MB) and its stack
// 180 MB of address space, touched only as far as a step needs.
int ContactCapacity(const WorldParams& world);
int ConstraintCapacity(const WorldParams& world);

// The builder holding the world's MJCF (for inspection or export).
sim::MjcfBuilder WorldMjcf(const WorldParams& world);
// Compiles the world's model. Throws MujocoError (never for a Validate()d
// world).
sim::ModelPtr BuildWorldModel(const WorldParams& world);
// True if a model built for `a` simulates `b` as well: they differ at most
// in start positions and target.
bool SameStructure(const WorldParams& a, const WorldParams& b);

}  // namespace manyworlds::boxworld

#endif  // MANYWORLDS_BOXWORLD_WORLD_MODEL_H_
