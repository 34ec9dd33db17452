// The wall family (Meta-World v3's reach-wall, push-wall, pick-place-wall):
// the base tasks' objects with a static wall between the start and the goal.
// Ranges from v3: object (-0.05, 0.6)-(0.05, 0.65), goals (-0.05, 0.85)-
// (0.05, 0.9) in xy; the wall spans x in [-0.02, 0.22], y in [0.74, 0.76],
// z up to 0.12 (assets/*_wall.xml).
#ifndef MANYWORLDS_MANIPULATION_WALL_H_
#define MANYWORLDS_MANIPULATION_WALL_H_

#include <span>
#include <string>

#include "manyworlds/manipulation/policy_utils.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation::wall {

inline constexpr double kWallTop = 0.12;
inline constexpr double kWallFarY = 0.76;
// Carrying height that clears the wall with a held 4 cm puck.
inline constexpr double kOverWall = 0.17;

// Task `id`'s config with the ranges all three share; the goal's z range
// is the task's.
SawyerTaskConfig WallConfig(std::string id, std::string description, std::string xml_file,
                            double goal_z_low, double goal_z_high);

// The long-tail tolerance of the object's weighted distance to `midpoint`
// (a point past the wall's end or over it) within `radius`, margin the same
// distance at reset: the first leg of push-wall's and pick-place-wall's
// rewards.
double TowardMidpoint(const SawyerState& state, const Vec3& midpoint, const Vec3& weights,
                      double radius);

// Grasp the puck, lift it over the wall, then carry it to `goal` (the
// puck's centre at the end).
void CarryOverWall(const SawyerObs& obs, const Vec3& goal, std::span<float> action);

}  // namespace manyworlds::manipulation::wall

#endif  // MANYWORLDS_MANIPULATION_WALL_H_
