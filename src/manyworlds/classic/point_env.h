// PointEnv: what the 2-D point navigation envs (point-nav, point-nav-sparse)
// share. A point starts every episode at (0, 0) and moves by the action:
//
//   action:   Box(-0.1, 0.1, (2,)), added to the position (out-of-range
//             actions are clipped by Env).
//   env_obs:  the position, Box(-inf, inf, (2,)).
//   task_obs: the goal (zeros if hide_task); its box is the derived env's.
//   info:     success; distance = ||position - goal|| after the move.
//   end:      never terminates; truncated after `horizon` steps.
//
// A derived env gives its task (which sets the goal through SetGoal), its
// reward and its success rule, both functions of the distance.
#ifndef MANYWORLDS_CLASSIC_POINT_ENV_H_
#define MANYWORLDS_CLASSIC_POINT_ENV_H_

#include <array>
#include <cstdint>
#include <span>

#include "manyworlds/core/env.h"

namespace manyworlds::classic {

class PointEnv : public Env {
 public:
  static constexpr float kMaxStep = 0.1f;

  const std::array<double, 2>& goal() const { return goal_; }
  const std::array<double, 2>& position() const { return position_; }

 protected:
  // The spec's shared fields (all but the description and the task
  // observation). Throws ConfigError on a horizon below 1.
  static EnvSpec BaseSpec(const char* id, int64_t horizon);

  PointEnv(EnvSpec spec, bool hide_task);

  // Sets the goal and the task observation.
  void SetGoal(double x, double y);
  // The reward and the success of a step that ends `distance` from the goal.
  virtual float Reward(double distance) const = 0;
  virtual bool Success(double distance) const = 0;

  void DoReset(const ObsView& out) final;
  void DoStep(std::span<const float> action, const StepView& out) final;

 private:
  bool hide_task_;
  std::array<double, 2> goal_{};
  std::array<double, 2> position_{};
};

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_POINT_ENV_H_
