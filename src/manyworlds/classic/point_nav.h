// 2-D point navigation with a dense reward, the classic meta-RL toy
// (MAML's point env, learn2learn's Particles2D): reach a hidden goal.
//
//   action:   Box(-0.1, 0.1, (2,)), added to the position (out-of-range
//             actions are clipped by Env).
//   env_obs:  the position, Box(-inf, inf, (2,)). Every episode starts at
//             (0, 0).
//   task_obs: the goal, Box(-r, r, (2,)) for r = goal_range (zeros if
//             hide_task).
//   reward:   -||position - goal|| after the move.
//   end:      never terminates (terminating near the goal, as MAML does,
//             hurts learning stability); truncated after `horizon` steps.
//   info:     success = 1 when the distance is < 0.05; distance.
//   task state params: {"goal": [2 numbers in [-r, r]]}, drawn U[-r, r]^2.
//   options:  goal_range (float, 0.5, in (0, 100]), horizon (int, 100,
//             >= 1), hide_task (bool, false).
#ifndef MANYWORLDS_CLASSIC_POINT_NAV_H_
#define MANYWORLDS_CLASSIC_POINT_NAV_H_

#include <cstdint>

#include "manyworlds/classic/point_env.h"

namespace manyworlds::classic {

class PointNavEnv : public PointEnv {
 public:
  static constexpr const char* kId = "point-nav";
  static constexpr double kSuccessDistance = 0.05;

  struct Config {
    double goal_range = 0.5;
    int64_t horizon = 100;
    bool hide_task = false;
  };

  // Throws ConfigError on an out-of-range option.
  explicit PointNavEnv(const Config& config);

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  float Reward(double distance) const override { return static_cast<float>(-distance); }
  bool Success(double distance) const override { return distance < kSuccessDistance; }

 private:
  static EnvSpec MakeSpec(const Config& config);

  double goal_range_;
};

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_POINT_NAV_H_
