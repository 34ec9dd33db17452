#include "manyworlds/dmc/rewards.h"

#include <limits>

#include "manyworlds/dmc/tolerance.h"

namespace manyworlds::dmc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

double FingerSpinReward(double hinge_velocity) {
  return hinge_velocity <= -kSpinVelocity ? 1.0 : 0.0;
}

double CheetahRunReward(double com_velocity_x) {
  return Tolerance(com_velocity_x, {.lower = kCheetahRunSpeed,
                                    .upper = kInf,
                                    .margin = kCheetahRunSpeed,
                                    .sigmoid = Sigmoid::kLinear,
                                    .value_at_margin = 0.0});
}

double WalkerWalkReward(double torso_height, double torso_upright, double com_velocity_x) {
  const double standing = Tolerance(torso_height, {.lower = kWalkerStandHeight,
                                                   .upper = kInf,
                                                   .margin = kWalkerStandHeight / 2,
                                                   .sigmoid = Sigmoid::kGaussian,
                                                   .value_at_margin = 0.1});
  const double upright = (1.0 + torso_upright) / 2.0;
  const double stand = (3.0 * standing + upright) / 4.0;
  const double move = Tolerance(com_velocity_x, {.lower = kWalkerWalkSpeed,
                                                 .upper = kInf,
                                                 .margin = kWalkerWalkSpeed / 2,
                                                 .sigmoid = Sigmoid::kLinear,
                                                 .value_at_margin = 0.5});
  return stand * (5.0 * move + 1.0) / 6.0;
}

}  // namespace manyworlds::dmc
