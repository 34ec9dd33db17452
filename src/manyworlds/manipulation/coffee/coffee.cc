#include "manyworlds/manipulation/coffee/coffee.h"

#include <cmath>

namespace manyworlds::manipulation::coffee {
namespace {

// The foot's height at rest on our table (measured; the cup's bottom is
// 2.8 mm above the foot), and v3's yaw at reset: its quaternion's z.
constexpr double kRestHeight = -0.0028118;
constexpr double kYawQuatZ = -0.02984;

}  // namespace

void PlaceMug(mjData* d, int qpos, int dof, double x, double y) {
  const mjtNum pose[7] = {x, y, kRestHeight, std::sqrt(1.0 - kYawQuatZ * kYawQuatZ), 0.0, 0.0,
                          kYawQuatZ};
  mju_copy(d->qpos + qpos, pose, 7);
  mju_zero(d->qvel + dof, 6);
  mju_zero(d->qacc_warmstart + dof, 6);
}

}  // namespace manyworlds::manipulation::coffee
