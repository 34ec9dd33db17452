// Multi-task cart-pole: Gym's CartPole (Euler integration, tau = 0.02)
// whose physical constants are set by a task vector mu in [-1, 1]^5, after
// MTEnv's MTCartPole.
//
//   task params:  gravity     = 9.8 + 5 * mu0
//                 cart mass   = 1.0 + 0.5 * mu1
//                 pole mass   = 0.1 + 0.09 * mu2
//                 half length = 0.5 + 0.3 * mu3
//                 force       = 10 + 5 * mu4
//     MTEnv uses force = 10 * mu4. We deviate on purpose: forces near zero
//     make a task uncontrollable and negative ones swap the meaning of the
//     two actions, so the task distribution would mix in degenerate tasks.
//     mu = 0 gives Gym's constants exactly.
//   action:   Discrete(2): 0 pushes left, 1 pushes right.
//   env_obs:  [x, x_dot, theta, theta_dot]; Box with |x| <= 4.8,
//             |theta| <= 24 deg (twice the termination limits, as Gym),
//             velocities unbounded.
//   task_obs: mu, Box(-1, 1, (5,)) (zeros if hide_task).
//   reward:   1 per step, the terminating step included (as Gym).
//   end:      terminated when |x| > 2.4 or |theta| > 12 deg; truncated after
//             `horizon` steps. Initial state U(-0.05, 0.05)^4 from the env
//             generator.
//   info:     success = 1 on the last step of an episode that reached the
//             step limit without terminating (never 1 if there is no limit).
//   task state params: {"mu": [5 numbers in [-1, 1]]}, drawn U[-1, 1].
//   options:  horizon (int, 500, >= 1), hide_task (bool, false).
#ifndef MANYWORLDS_CLASSIC_CARTPOLE_H_
#define MANYWORLDS_CLASSIC_CARTPOLE_H_

#include "manyworlds/classic/task_vector_env.h"

namespace manyworlds::classic {

struct CartPolePhysics {
  double gravity = 9.8;
  double cart_mass = 1.0;
  double pole_mass = 0.1;
  double half_length = 0.5;
  double force = 10.0;
};

// State: x, x_dot, theta, theta_dot.
class CartPoleEnv : public TaskVectorEnv<CartPolePhysics> {
 public:
  using Physics = CartPolePhysics;
  static constexpr const char* kId = "cartpole";
  static constexpr double kTau = 0.02;
  static constexpr double kXThreshold = 2.4;
  static constexpr double kThetaThreshold = 12.0 * 2.0 * 3.14159265358979323846 / 360.0;

  // Throws ConfigError on an out-of-range option.
  explicit CartPoleEnv(const Config& config);

  static Physics PhysicsFromMu(const TaskVector& mu);
  // One Euler step of Gym's cart-pole equations.
  static State Integrate(const Physics& physics, const State& state, int action);

 protected:
  void WriteObs(std::span<float> env_obs) const override;
  void DoStep(std::span<const float> action, const StepView& out) override;
};

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_CARTPOLE_H_
