// Two-goal T-maze, a grid version of MTEnv's two-goal maze: the maze is the
// same for every task; the task says which end of the bar pays.
//
//   Map (y grows upward, x to the right; outside the map is wall):
//
//        x: 0123456
//     y=4   A.....B    A: goal 0, B: goal 1 (ends of the bar)
//     y=3   ###.###
//     y=2   ###.###
//     y=1   ###.###
//     y=0   ###S###    S: start, at the bottom of the stem
//
//   action:   Discrete(4): 0 up (y+1), 1 down, 2 left, 3 right. Moving
//             into a wall leaves the agent where it is.
//   env_obs:  Box(0, 1, (2,)): (x / 6, y / 4).
//   task_obs: Box(0, 1, (1,)): the paying goal index (zeros if hide_task).
//   reward:   -0.01 per step; a step that enters the paying goal gives
//             exactly +1 instead, the other goal exactly -1.
//   end:      terminated on entering either goal; truncated after `horizon`
//             steps. The shortest path to a goal takes 7 steps.
//   info:     success = 1 on the step that enters the paying goal.
//   task state params: {"goal": 0 or 1}, drawn uniformly by the task
//             generator. The dynamics are deterministic (no env generator).
//   options:  horizon (int, 50, >= 1), hide_task (bool, false).
#ifndef MANYWORLDS_CLASSIC_TWO_GOAL_MAZE_H_
#define MANYWORLDS_CLASSIC_TWO_GOAL_MAZE_H_

#include <cstdint>

#include "manyworlds/core/env.h"

namespace manyworlds::classic {

class TwoGoalMazeEnv : public Env {
 public:
  static constexpr const char* kId = "two-goal-maze";
  static constexpr int kWidth = 7;
  static constexpr int kHeight = 5;
  enum Action { kUp = 0, kDown = 1, kLeft = 2, kRight = 3 };

  struct Config {
    int64_t horizon = 50;
    bool hide_task = false;
  };

  // Throws ConfigError on an out-of-range option.
  explicit TwoGoalMazeEnv(const Config& config);

  int goal() const { return goal_; }
  int x() const { return x_; }
  int y() const { return y_; }

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  static EnvSpec MakeSpec(const Config& config);
  void WriteObs(std::span<float> env_obs) const;

  bool hide_task_;
  int goal_ = 0;
  int x_ = 0;
  int y_ = 0;
};

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_TWO_GOAL_MAZE_H_
