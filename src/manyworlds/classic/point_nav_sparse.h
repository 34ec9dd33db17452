// 2-D point navigation with a sparse reward (PEARL's sparse point robot):
// goals lie on the upper half of the unit circle and only a disc around the
// goal pays, so the agent must explore to find it.
//
//   action:   Box(-0.1, 0.1, (2,)), added to the position (clipped by Env).
//   env_obs:  the position, Box(-inf, inf, (2,)); start at (0, 0).
//   task_obs: the goal (cos a, sin a), Box([-1, 0], [1, 1]) (zeros if
//             hide_task).
//   reward:   1 when ||position - goal|| <= goal_radius after the move,
//             else 0.
//   end:      never terminates; truncated after `horizon` steps. A goal at
//             distance 1 needs at least 8 steps of 0.1 per axis, hence the
//             default horizon of 30.
//   info:     success = 1 inside the goal radius; distance.
//   task state params: {"angle": number in [0, pi]}, drawn U[0, pi]; the
//             goal is (cos angle, sin angle).
//   options:  goal_radius (float, 0.2, in (0, 2]), horizon (int, 30, >= 1),
//             hide_task (bool, false).
#ifndef MANYWORLDS_CLASSIC_POINT_NAV_SPARSE_H_
#define MANYWORLDS_CLASSIC_POINT_NAV_SPARSE_H_

#include <cstdint>
#include <numbers>

#include "manyworlds/classic/point_env.h"

namespace manyworlds::classic {

class PointNavSparseEnv : public PointEnv {
 public:
  static constexpr const char* kId = "point-nav-sparse";
  static constexpr double kPi = std::numbers::pi;

  struct Config {
    double goal_radius = 0.2;
    int64_t horizon = 30;
    bool hide_task = false;
  };

  // Throws ConfigError on an out-of-range option.
  explicit PointNavSparseEnv(const Config& config);

  double angle() const { return angle_; }

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  float Reward(double distance) const override { return Success(distance) ? 1.0f : 0.0f; }
  bool Success(double distance) const override { return distance <= goal_radius_; }

 private:
  static EnvSpec MakeSpec(const Config& config);

  double goal_radius_;
  double angle_ = 0.0;
};

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_POINT_NAV_SPARSE_H_
