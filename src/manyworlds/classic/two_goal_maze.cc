#include "manyworlds/classic/two_goal_maze.h"

#include "manyworlds/classic/common.h"

namespace manyworlds::classic {
namespace {

// Top row first; see the header for the legend.
// clang-format off
constexpr const char* kMap[TwoGoalMazeEnv::kHeight] = {
    "A.....B",
    "###.###",
    "###.###",
    "###.###",
    "###S###",
};
// clang-format on
constexpr int kStartX = 3;
constexpr int kStartY = 0;
constexpr float kStepCost = -0.01f;

char Cell(int x, int y) {
  if (x < 0 || x >= TwoGoalMazeEnv::kWidth || y < 0 || y >= TwoGoalMazeEnv::kHeight) return '#';
  return kMap[TwoGoalMazeEnv::kHeight - 1 - y][x];
}

}  // namespace

EnvSpec TwoGoalMazeEnv::MakeSpec(const Config& config) {
  CheckIntOption(kId, "horizon", config.horizon, 1);
  EnvSpec spec;
  spec.id = kId;
  spec.description = "Grid T-maze with two goals; the task says which goal pays";
  spec.action_space = Space::Discrete(4);
  spec.env_obs_space = Space::Box(0.0f, 1.0f, {2});
  spec.task_obs_space = Space::Box(0.0f, 1.0f, {1});
  spec.info_fields = {"success"};
  spec.max_episode_steps = config.horizon;
  spec.uses_env_seed = false;  // fixed start, deterministic moves
  return spec;
}

TwoGoalMazeEnv::TwoGoalMazeEnv(const Config& config)
    : Env(MakeSpec(config)), hide_task_(config.hide_task) {}

TaskState TwoGoalMazeEnv::DoSampleTaskState(Rng& task_rng) {
  return TaskState{kId, {{"goal", static_cast<int64_t>(task_rng.UniformInt(2))}}};
}

TaskState TwoGoalMazeEnv::DoGetTaskState() const {
  return TaskState{kId, {{"goal", static_cast<int64_t>(goal_)}}};
}

void TwoGoalMazeEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, kId);
  reader.ExpectKeys({"goal"});
  goal_ = static_cast<int>(reader.Integer("goal", 0, 1));
  const float obs[1] = {hide_task_ ? 0.0f : static_cast<float>(goal_)};
  SetTaskObs(obs);
}

void TwoGoalMazeEnv::WriteObs(std::span<float> env_obs) const {
  env_obs[0] = static_cast<float>(x_) / (kWidth - 1);
  env_obs[1] = static_cast<float>(y_) / (kHeight - 1);
}

void TwoGoalMazeEnv::DoReset(const ObsView& out) {
  x_ = kStartX;
  y_ = kStartY;
  WriteObs(out.env_obs);
}

void TwoGoalMazeEnv::DoStep(std::span<const float> action, const StepView& out) {
  static constexpr int kDx[4] = {0, 0, -1, 1};
  static constexpr int kDy[4] = {1, -1, 0, 0};
  const int a = static_cast<int>(action[0]);
  const int nx = x_ + kDx[a];
  const int ny = y_ + kDy[a];
  if (Cell(nx, ny) != '#') {
    x_ = nx;
    y_ = ny;
  }
  WriteObs(out.env_obs);
  const char cell = Cell(x_, y_);
  if (cell == 'A' || cell == 'B') {
    const bool paid = (cell == 'A' ? 0 : 1) == goal_;
    *out.reward = paid ? 1.0f : -1.0f;
    *out.terminated = true;
    out.info[0] = paid ? 1.0f : 0.0f;
  } else {
    *out.reward = kStepCost;
  }
}

}  // namespace manyworlds::classic
