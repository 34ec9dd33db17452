#include "manyworlds/classic/point_nav.h"

#include <cmath>
#include <limits>
#include <vector>

#include "manyworlds/classic/common.h"

namespace manyworlds::classic {

EnvSpec PointNavEnv::MakeSpec(const Config& config) {
  const double r = CheckFloatOption(kId, "goal_range", config.goal_range, 0.0, 100.0);
  CheckIntOption(kId, "horizon", config.horizon, 1);
  const float inf = std::numeric_limits<float>::infinity();
  EnvSpec spec;
  spec.id = kId;
  spec.description = "2-D point navigation to a goal in a square, dense reward";
  spec.action_space = Space::Box(-kMaxStep, kMaxStep, {2});
  spec.env_obs_space = Space::Box(-inf, inf, {2});
  spec.task_obs_space = Space::Box(-static_cast<float>(r), static_cast<float>(r), {2});
  spec.info_fields = {"success", "distance"};
  spec.max_episode_steps = config.horizon;
  spec.uses_env_seed = false;  // fixed start, deterministic moves
  return spec;
}

PointNavEnv::PointNavEnv(const Config& config)
    : Env(MakeSpec(config)), goal_range_(config.goal_range), hide_task_(config.hide_task) {}

TaskState PointNavEnv::DoSampleTaskState(Rng& task_rng) {
  const double x = task_rng.Uniform(-goal_range_, goal_range_);
  const double y = task_rng.Uniform(-goal_range_, goal_range_);
  return TaskState{kId, {{"goal", std::vector<double>{x, y}}}};
}

TaskState PointNavEnv::DoGetTaskState() const {
  return TaskState{kId, {{"goal", std::vector<double>{goal_[0], goal_[1]}}}};
}

void PointNavEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, kId);
  reader.ExpectKeys({"goal"});
  const auto goal = reader.Numbers("goal", 2, -goal_range_, goal_range_);
  goal_ = {goal[0], goal[1]};
  const float obs[2] = {hide_task_ ? 0.0f : static_cast<float>(goal_[0]),
                        hide_task_ ? 0.0f : static_cast<float>(goal_[1])};
  SetTaskObs(obs);
}

void PointNavEnv::DoReset(const ObsView& out) {
  position_ = {0.0, 0.0};
  out.env_obs[0] = 0.0f;
  out.env_obs[1] = 0.0f;
}

void PointNavEnv::DoStep(std::span<const float> action, const StepView& out) {
  position_[0] += action[0];
  position_[1] += action[1];
  const double distance = std::hypot(position_[0] - goal_[0], position_[1] - goal_[1]);
  out.env_obs[0] = static_cast<float>(position_[0]);
  out.env_obs[1] = static_cast<float>(position_[1]);
  *out.reward = static_cast<float>(-distance);
  out.info[0] = distance < kSuccessDistance ? 1.0f : 0.0f;
  out.info[1] = static_cast<float>(distance);
}

}  // namespace manyworlds::classic
