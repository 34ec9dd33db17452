#include "manyworlds/classic/cartpole.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "manyworlds/classic/common.h"

namespace manyworlds::classic {

EnvSpec CartPoleEnv::MakeSpec(const Config& config) {
  CheckIntOption(kId, "horizon", config.horizon, 1);
  const float inf = std::numeric_limits<float>::infinity();
  const auto x_max = static_cast<float>(2.0 * kXThreshold);
  const auto theta_max = static_cast<float>(2.0 * kThetaThreshold);
  EnvSpec spec;
  spec.id = kId;
  spec.description = "Cart-pole with task-dependent gravity, masses, pole length and force";
  spec.action_space = Space::Discrete(2);
  spec.env_obs_space =
      Space::Box({-x_max, -inf, -theta_max, -inf}, {x_max, inf, theta_max, inf}, {4});
  spec.task_obs_space = Space::Box(-1.0f, 1.0f, {kTaskDim});
  spec.info_fields = {"success"};
  spec.max_episode_steps = config.horizon;
  return spec;
}

CartPoleEnv::CartPoleEnv(const Config& config)
    : Env(MakeSpec(config)), hide_task_(config.hide_task) {}

CartPoleEnv::Physics CartPoleEnv::PhysicsFromMu(const std::array<double, kTaskDim>& mu) {
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

TaskState CartPoleEnv::DoSampleTaskState(Rng& task_rng) {
  std::vector<double> mu(kTaskDim);
  for (double& m : mu) m = task_rng.Uniform(-1.0, 1.0);
  return TaskState{kId, {{"mu", mu}}};
}

TaskState CartPoleEnv::DoGetTaskState() const {
  return TaskState{kId, {{"mu", std::vector<double>(mu_.begin(), mu_.end())}}};
}

void CartPoleEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, kId);
  reader.ExpectKeys({"mu"});
  const auto mu = reader.Numbers("mu", kTaskDim, -1.0, 1.0);
  std::copy(mu.begin(), mu.end(), mu_.begin());
  physics_ = PhysicsFromMu(mu_);
  float obs[kTaskDim] = {};
  for (int i = 0; i < kTaskDim; ++i) obs[i] = hide_task_ ? 0.0f : static_cast<float>(mu_[i]);
  SetTaskObs(obs);
}

void CartPoleEnv::WriteObs(std::span<float> env_obs) const {
  for (int i = 0; i < 4; ++i) env_obs[i] = static_cast<float>(state_[i]);
}

void CartPoleEnv::DoReset(const ObsView& out) {
  for (double& v : state_) v = env_rng().Uniform(-0.05, 0.05);
  WriteObs(out.env_obs);
}

void CartPoleEnv::DoStep(std::span<const float> action, const StepView& out) {
  state_ = Integrate(physics_, state_, static_cast<int>(action[0]));
  WriteObs(out.env_obs);
  const bool fell = std::abs(state_[0]) > kXThreshold || std::abs(state_[2]) > kThetaThreshold;
  *out.reward = 1.0f;
  *out.terminated = fell;
  // elapsed_steps() counts the steps before this one.
  const int64_t limit = spec().max_episode_steps;
  out.info[0] = !fell && limit > 0 && elapsed_steps() + 1 >= limit ? 1.0f : 0.0f;
}

}  // namespace manyworlds::classic
