#include "manyworlds/classic/point_nav_sparse.h"

#include <cmath>

#include "manyworlds/classic/common.h"

namespace manyworlds::classic {

EnvSpec PointNavSparseEnv::MakeSpec(const Config& config) {
  CheckFloatOption(kId, "goal_radius", config.goal_radius, 0.0, 2.0);
  EnvSpec spec = BaseSpec(kId, config.horizon);
  spec.description = "2-D point navigation to a goal on the unit half-circle, sparse reward";
  spec.task_obs_space = Space::Box({-1.0f, 0.0f}, {1.0f, 1.0f}, {2});
  return spec;
}

PointNavSparseEnv::PointNavSparseEnv(const Config& config)
    : PointEnv(MakeSpec(config), config.hide_task), goal_radius_(config.goal_radius) {}

TaskState PointNavSparseEnv::DoSampleTaskState(Rng& task_rng) {
  return TaskState{kId, {{"angle", task_rng.Uniform(0.0, kPi)}}};
}

TaskState PointNavSparseEnv::DoGetTaskState() const { return TaskState{kId, {{"angle", angle_}}}; }

void PointNavSparseEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, kId);
  reader.ExpectKeys({"angle"});
  angle_ = reader.Number("angle", 0.0, kPi);
  // sin is >= 0 on [0, pi] in double as well (sin(pi) ~ 1.2e-16).
  SetGoal(std::cos(angle_), std::sin(angle_));
}

}  // namespace manyworlds::classic
