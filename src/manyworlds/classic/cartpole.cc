#include "manyworlds/classic/cartpole.h"

#include <cmath>
#include <limits>

namespace manyworlds::classic {

namespace {

// Twice the termination limits (as Gym); the velocities unbounded.
Space ObsSpace() {
  const float inf = std::numeric_limits<float>::infinity();
  const auto x_max = static_cast<float>(2.0 * CartPoleEnv::kXThreshold);
  const auto theta_max = static_cast<float>(2.0 * CartPoleEnv::kThetaThreshold);
  return Space::Box({-x_max, -inf, -theta_max, -inf}, {x_max, inf, theta_max, inf}, {4});
}

}  // namespace

CartPoleEnv::CartPoleEnv(const Config& config)
    : TaskVectorEnv(MakeSpec(kId, config,
                             "Cart-pole with task-dependent gravity, masses, pole length and "
                             "force",
                             Space::Discrete(2), ObsSpace()),
                    config, &PhysicsFromMu, /*reset_noise=*/0.05) {}

CartPoleEnv::Physics CartPoleEnv::PhysicsFromMu(const TaskVector& mu) {
  Physics p;
  p.gravity = 9.8 + 5.0 * mu[0];
  p.cart_mass = 1.0 + 0.5 * mu[1];
  p.pole_mass = 0.1 + 0.09 * mu[2];
  p.half_length = 0.5 + 0.3 * mu[3];
  p.force = 10.0 + 5.0 * mu[4];
  return p;
}

CartPoleEnv::State CartPoleEnv::Integrate(const Physics& p, const State& s, int action) {
  const double force = action == 1 ? p.force : -p.force;
  const double total_mass = p.cart_mass + p.pole_mass;
  const double pole_mass_length = p.pole_mass * p.half_length;
  const double cos_theta = std::cos(s[2]);
  const double sin_theta = std::sin(s[2]);
  const double temp = (force + pole_mass_length * s[3] * s[3] * sin_theta) / total_mass;
  const double theta_acc =
      (p.gravity * sin_theta - cos_theta * temp) /
      (p.half_length * (4.0 / 3.0 - p.pole_mass * cos_theta * cos_theta / total_mass));
  const double x_acc = temp - pole_mass_length * theta_acc * cos_theta / total_mass;
  // Explicit Euler: positions use the old velocities, as Gym's default.
  return State{s[0] + kTau * s[1], s[1] + kTau * x_acc, s[2] + kTau * s[3],
               s[3] + kTau * theta_acc};
}

void CartPoleEnv::WriteObs(std::span<float> env_obs) const {
  for (int i = 0; i < 4; ++i) env_obs[i] = static_cast<float>(state_[i]);
}

void CartPoleEnv::DoStep(std::span<const float> action, const StepView& out) {
  state_ = Integrate(physics(), state_, static_cast<int>(action[0]));
  WriteObs(out.env_obs);
  const bool fell = std::abs(state_[0]) > kXThreshold || std::abs(state_[2]) > kThetaThreshold;
  *out.reward = 1.0f;
  *out.terminated = fell;
  // elapsed_steps() counts the steps before this one.
  const int64_t limit = spec().max_episode_steps;
  out.info[0] = !fell && limit > 0 && elapsed_steps() + 1 >= limit ? 1.0f : 0.0f;
}

}  // namespace manyworlds::classic
