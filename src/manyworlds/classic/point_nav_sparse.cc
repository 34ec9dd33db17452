#include "manyworlds/classic/point_nav_sparse.h"

#include <cmath>
#include <limits>

#include "manyworlds/classic/common.h"

namespace manyworlds::classic {

EnvSpec PointNavSparseEnv::MakeSpec(const Config& config) {
  CheckFloatOption(kId, "goal_radius", config.goal_radius, 0.0, 2.0);
  CheckIntOption(kId, "horizon", config.horizon, 1);
  const float inf = std::numeric_limits<float>::infinity();
  EnvSpec spec;
  spec.id = kId;
  spec.description = "2-D point navigation to a goal on the unit half-circle, sparse reward";
  spec.action_space = Space::Box(-kMaxStep, kMaxStep, {2});
  spec.env_obs_space = Space::Box(-inf, inf, {2});
  spec.task_obs_space = Space::Box({-1.0f, 0.0f}, {1.0f, 1.0f}, {2});
  spec.info_fields = {"success", "distance"};
  spec.max_episode_steps = config.horizon;
  spec.uses_env_seed = false;  // fixed start, deterministic moves
  return spec;
}

PointNavSparseEnv::PointNavSparseEnv(const Config& config)
    : Env(MakeSpec(config)), goal_radius_(config.goal_radius), hide_task_(config.hide_task) {}

TaskState PointNavSparseEnv::DoSampleTaskState(Rng& task_rng) {
  return TaskState{kId, {{"angle", task_rng.Uniform(0.0, kPi)}}};
}

TaskState PointNavSparseEnv::DoGetTaskState() const { return TaskState{kId, {{"angle", angle_}}}; }

void PointNavSparseEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, kId);
  reader.ExpectKeys({"angle"});
  angle_ = reader.Number("angle", 0.0, kPi);
  // sin is >= 0 on [0, pi] in double as well (sin(pi) ~ 1.2e-16).
  goal_ = {std::cos(angle_), std::sin(angle_)};
  const float obs[2] = {hide_task_ ? 0.0f : static_cast<float>(goal_[0]),
                        hide_task_ ? 0.0f : static_cast<float>(goal_[1])};
  SetTaskObs(obs);
}

void PointNavSparseEnv::DoReset(const ObsView& out) {
  position_ = {0.0, 0.0};
  out.env_obs[0] = 0.0f;
  out.env_obs[1] = 0.0f;
}

void PointNavSparseEnv::DoStep(std::span<const float> action, const StepView& out) {
  position_[0] += action[0];
  position_[1] += action[1];
  const double distance = std::hypot(position_[0] - goal_[0], position_[1] - goal_[1]);
  const bool inside = distance <= goal_radius_;
  out.env_obs[0] = static_cast<float>(position_[0]);
  out.env_obs[1] = static_cast<float>(position_[1]);
  *out.reward = inside ? 1.0f : 0.0f;
  out.info[0] = inside ? 1.0f : 0.0f;
  out.info[1] = static_cast<float>(distance);
}

}  // namespace manyworlds::classic
