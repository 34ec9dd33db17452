// The rewards of dm_control's finger-spin, cheetah-run and walker-walk as pure functions of
// the physical quantities they read (docs/reference/dmc_hipbmdp.md, section 2.2), so that a
// test can feed them quantities recorded from dm_control itself
// (tests/dmc/data/dmc_rewards.json, written by scripts/record_dmc_rewards.py). Every reward
// lies in [0, 1] per control step.
#ifndef MANYWORLDS_DMC_REWARDS_H_
#define MANYWORLDS_DMC_REWARDS_H_

namespace manyworlds::dmc {

// finger-spin: the spinner must turn at 15 rad/s or faster in the negative sense of its hinge.
inline constexpr double kSpinVelocity = 15.0;
// cheetah-run: full reward from this centre-of-mass speed on (m/s).
inline constexpr double kCheetahRunSpeed = 10.0;
// walker: the torso stands from this height on (m); walk speed (m/s).
inline constexpr double kWalkerStandHeight = 1.2;
inline constexpr double kWalkerWalkSpeed = 1.0;

// 1 if hinge_velocity <= -kSpinVelocity (rad/s, the spinner hinge's joint velocity), else 0.
double FingerSpinReward(double hinge_velocity);

// Linear ramp of the centre-of-mass x velocity (the torso's subtree linear velocity, m/s):
// 0 at or below 0, 1 at or above kCheetahRunSpeed.
double CheetahRunReward(double com_velocity_x);

// Standing times moving. torso_height: world z of the torso body's origin (m); torso_upright:
// the zz entry of the torso's rotation matrix (1 upright, -1 upside down); com_velocity_x:
// the torso's subtree linear x velocity (m/s).
//   standing = Tolerance(height, [1.2, inf), margin 0.6, gaussian, 0.1 at the margin)
//   stand    = (3 standing + (1 + upright) / 2) / 4
//   move     = Tolerance(vx, [1, inf), margin 0.5, linear, 0.5 at the margin)
//   reward   = stand (5 move + 1) / 6
double WalkerWalkReward(double torso_height, double torso_upright, double com_velocity_x);

}  // namespace manyworlds::dmc

#endif  // MANYWORLDS_DMC_REWARDS_H_
