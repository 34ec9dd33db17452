// Multi-task acrobot: Gym's Acrobot ("book" dynamics, one RK4 step of
// dt = 0.2 per action, no torque noise) whose links are set by a task vector
// mu in [-1, 1]^5, after MTEnv's MTAcrobot.
//
//   task params:  link lengths l1 = 1 + 0.5 * mu0, l2 = 1 + 0.5 * mu1
//                 link masses  m1 = 1 + 0.5 * mu2, m2 = 1 + 0.5 * mu3
//                 torque sign  -1 if mu4 < 0, else +1
//     Each link's centre of mass sits at half its length (Gym: 0.5 for a
//     unit link); the moments of inertia stay Gym's 1, so mu = 0 reproduces
//     Gym exactly. (MTEnv samples 7 values and reads mu[6] for the flip; we
//     keep the 5 that are used.)
//   action:   Discrete(3): torque {-1, 0, +1} on the second joint, times the
//             task's torque sign.
//   env_obs:  [cos t1, sin t1, cos t2, sin t2, t1_dot, t2_dot]; Box with
//             |t1_dot| <= 4 pi, |t2_dot| <= 9 pi (the velocity limits).
//             Angles are wrapped to [-pi, pi].
//   task_obs: mu, Box(-1, 1, (5,)) (zeros if hide_task).
//   reward:   -1 per step, 0 on the terminating step.
//   end:      terminated when the tip rises above the pivot by more than half
//             the arm's reach: -l1 cos t1 - l2 cos(t1 + t2) > (l1 + l2) / 2.
//             With unit links this is Gym's -cos t1 - cos(t1 + t2) > 1, and
//             it asks every task for the same fraction of its reach.
//             Truncated after `horizon` steps. Initial state
//             U(-0.1, 0.1)^4 from the env generator.
//   info:     success = 1 on the terminating step.
//   task state params: {"mu": [5 numbers in [-1, 1]]}, drawn U[-1, 1].
//   options:  horizon (int, 500, >= 1), hide_task (bool, false).
#ifndef MANYWORLDS_CLASSIC_ACROBOT_H_
#define MANYWORLDS_CLASSIC_ACROBOT_H_

#include <numbers>

#include "manyworlds/classic/task_vector_env.h"

namespace manyworlds::classic {

struct AcrobotPhysics {
  double l1 = 1.0, l2 = 1.0;    // link lengths
  double m1 = 1.0, m2 = 1.0;    // link masses
  double lc1 = 0.5, lc2 = 0.5;  // centre-of-mass distances from the joints
  double i1 = 1.0, i2 = 1.0;    // moments of inertia
  double torque_sign = 1.0;
};

// State: t1, t2, t1_dot, t2_dot.
class AcrobotEnv : public TaskVectorEnv<AcrobotPhysics> {
 public:
  using Physics = AcrobotPhysics;
  static constexpr const char* kId = "acrobot";
  static constexpr double kDt = 0.2;
  static constexpr double kPi = std::numbers::pi;
  static constexpr double kMaxVel1 = 4.0 * kPi;
  static constexpr double kMaxVel2 = 9.0 * kPi;

  // Throws ConfigError on an out-of-range option.
  explicit AcrobotEnv(const Config& config);

  static Physics PhysicsFromMu(const TaskVector& mu);
  // Time derivative of the state under a torque (Gym's "book" equations).
  static State Derivative(const Physics& physics, const State& state, double torque);
  // One action step: RK4 over kDt, angle wrapping, velocity clipping.
  static State Integrate(const Physics& physics, const State& state, double torque);
  static bool IsTerminal(const Physics& physics, const State& state);

 protected:
  void WriteObs(std::span<float> env_obs) const override;
  void DoStep(std::span<const float> action, const StepView& out) override;
};

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_ACROBOT_H_
