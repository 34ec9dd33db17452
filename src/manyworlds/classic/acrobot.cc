#include "manyworlds/classic/acrobot.h"

#include <algorithm>
#include <cmath>

namespace manyworlds::classic {
namespace {

constexpr double kGravity = 9.8;

// Wraps an angle into [-pi, pi).
double WrapAngle(double angle) {
  if (angle >= -AcrobotEnv::kPi && angle < AcrobotEnv::kPi) return angle;
  const double period = 2.0 * AcrobotEnv::kPi;
  return angle - period * std::floor((angle + AcrobotEnv::kPi) / period);
}

// cos and sin of both angles, then the two velocities.
Space ObsSpace() {
  const auto v1 = static_cast<float>(AcrobotEnv::kMaxVel1);
  const auto v2 = static_cast<float>(AcrobotEnv::kMaxVel2);
  return Space::Box({-1.0f, -1.0f, -1.0f, -1.0f, -v1, -v2}, {1.0f, 1.0f, 1.0f, 1.0f, v1, v2}, {6});
}

}  // namespace

AcrobotEnv::AcrobotEnv(const Config& config)
    : TaskVectorEnv(MakeSpec(kId, config,
                             "Acrobot swing-up with task-dependent link lengths, masses and "
                             "torque sign",
                             Space::Discrete(3), ObsSpace()),
                    config, &PhysicsFromMu, /*reset_noise=*/0.1) {}

AcrobotEnv::Physics AcrobotEnv::PhysicsFromMu(const TaskVector& mu) {
  Physics p;
  p.l1 = 1.0 + 0.5 * mu[0];
  p.l2 = 1.0 + 0.5 * mu[1];
  p.m1 = 1.0 + 0.5 * mu[2];
  p.m2 = 1.0 + 0.5 * mu[3];
  p.lc1 = 0.5 * p.l1;
  p.lc2 = 0.5 * p.l2;
  p.torque_sign = mu[4] < 0.0 ? -1.0 : 1.0;
  return p;
}

AcrobotEnv::State AcrobotEnv::Derivative(const Physics& p, const State& s, double torque) {
  const double t1 = s[0], t2 = s[1], dt1 = s[2], dt2 = s[3];
  const double d1 = p.m1 * p.lc1 * p.lc1 +
                    p.m2 * (p.l1 * p.l1 + p.lc2 * p.lc2 + 2.0 * p.l1 * p.lc2 * std::cos(t2)) +
                    p.i1 + p.i2;
  const double d2 = p.m2 * (p.lc2 * p.lc2 + p.l1 * p.lc2 * std::cos(t2)) + p.i2;
  const double phi2 = p.m2 * p.lc2 * kGravity * std::cos(t1 + t2 - kPi / 2.0);
  const double phi1 = -p.m2 * p.l1 * p.lc2 * dt2 * dt2 * std::sin(t2) -
                      2.0 * p.m2 * p.l1 * p.lc2 * dt2 * dt1 * std::sin(t2) +
                      (p.m1 * p.lc1 + p.m2 * p.l1) * kGravity * std::cos(t1 - kPi / 2.0) + phi2;
  // The "book" variant keeps the dt1^2 term that the NIPS paper drops.
  const double ddt2 =
      (torque + d2 / d1 * phi1 - p.m2 * p.l1 * p.lc2 * dt1 * dt1 * std::sin(t2) - phi2) /
      (p.m2 * p.lc2 * p.lc2 + p.i2 - d2 * d2 / d1);
  const double ddt1 = -(d2 * ddt2 + phi1) / d1;
  return State{dt1, dt2, ddt1, ddt2};
}

AcrobotEnv::State AcrobotEnv::Integrate(const Physics& p, const State& s, double torque) {
  auto shifted = [&](const State& k, double h) {
    State out;
    for (int i = 0; i < 4; ++i) out[i] = s[i] + h * k[i];
    return out;
  };
  const State k1 = Derivative(p, s, torque);
  const State k2 = Derivative(p, shifted(k1, kDt / 2.0), torque);
  const State k3 = Derivative(p, shifted(k2, kDt / 2.0), torque);
  const State k4 = Derivative(p, shifted(k3, kDt), torque);
  State next;
  for (int i = 0; i < 4; ++i) {
    next[i] = s[i] + kDt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  }
  next[0] = WrapAngle(next[0]);
  next[1] = WrapAngle(next[1]);
  next[2] = std::clamp(next[2], -kMaxVel1, kMaxVel1);
  next[3] = std::clamp(next[3], -kMaxVel2, kMaxVel2);
  return next;
}

bool AcrobotEnv::IsTerminal(const Physics& p, const State& s) {
  const double tip_height = -p.l1 * std::cos(s[0]) - p.l2 * std::cos(s[0] + s[1]);
  return tip_height > 0.5 * (p.l1 + p.l2);
}

void AcrobotEnv::WriteObs(std::span<float> env_obs) const {
  env_obs[0] = static_cast<float>(std::cos(state_[0]));
  env_obs[1] = static_cast<float>(std::sin(state_[0]));
  env_obs[2] = static_cast<float>(std::cos(state_[1]));
  env_obs[3] = static_cast<float>(std::sin(state_[1]));
  env_obs[4] = static_cast<float>(state_[2]);
  env_obs[5] = static_cast<float>(state_[3]);
}

void AcrobotEnv::DoStep(std::span<const float> action, const StepView& out) {
  const double torque = physics().torque_sign * (static_cast<double>(action[0]) - 1.0);
  state_ = Integrate(physics(), state_, torque);
  WriteObs(out.env_obs);
  const bool terminal = IsTerminal(physics(), state_);
  *out.reward = terminal ? 0.0f : -1.0f;
  *out.terminated = terminal;
  out.info[0] = terminal ? 1.0f : 0.0f;
}

}  // namespace manyworlds::classic
