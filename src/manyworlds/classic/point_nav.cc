#include "manyworlds/classic/point_nav.h"

#include <vector>

#include "manyworlds/classic/common.h"

namespace manyworlds::classic {

EnvSpec PointNavEnv::MakeSpec(const Config& config) {
  const double r = CheckFloatOption(kId, "goal_range", config.goal_range, 0.0, 100.0);
  EnvSpec spec = BaseSpec(kId, config.horizon);
  spec.description = "2-D point navigation to a goal in a square, dense reward";
  spec.task_obs_space = Space::Box(-static_cast<float>(r), static_cast<float>(r), {2});
  return spec;
}

PointNavEnv::PointNavEnv(const Config& config)
    : PointEnv(MakeSpec(config), config.hide_task), goal_range_(config.goal_range) {}

TaskState PointNavEnv::DoSampleTaskState(Rng& task_rng) {
  const double x = task_rng.Uniform(-goal_range_, goal_range_);
  const double y = task_rng.Uniform(-goal_range_, goal_range_);
  return TaskState{kId, {{"goal", std::vector<double>{x, y}}}};
}

TaskState PointNavEnv::DoGetTaskState() const {
  return TaskState{kId, {{"goal", std::vector<double>{goal()[0], goal()[1]}}}};
}

void PointNavEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, kId);
  reader.ExpectKeys({"goal"});
  const auto goal = reader.Numbers("goal", 2, -goal_range_, goal_range_);
  SetGoal(goal[0], goal[1]);
}

}  // namespace manyworlds::classic
