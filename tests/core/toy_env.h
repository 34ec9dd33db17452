// A tiny multi-task env for core tests: a 1-D walker that must reach a
// target position. The task is the target; the env seed sets the start.
//   action: Box(-1, 1, (1,)) step size, or Discrete(3) {left, stay, right}
//   env_obs: [position, velocity]      task_obs: [target]
//   reward: -|position - target|; terminated when within 0.05 of target.
//   info: success, distance
#ifndef MANYWORLDS_TESTS_CORE_TOY_ENV_H_
#define MANYWORLDS_TESTS_CORE_TOY_ENV_H_

#include <cmath>
#include <limits>
#include <memory>

#include "manyworlds/core/env.h"
#include "manyworlds/core/error.h"

namespace manyworlds::testing {

class ToyEnv : public Env {
 public:
  explicit ToyEnv(bool discrete = false, int64_t max_steps = 50)
      : Env(MakeSpec(discrete, max_steps)), discrete_(discrete) {}

  static EnvSpec MakeSpec(bool discrete, int64_t max_steps) {
    const float inf = std::numeric_limits<float>::infinity();
    EnvSpec spec;
    spec.id = discrete ? "toy-discrete" : "toy";
    spec.description = "1-D walker that must reach a target (test env)";
    spec.action_space = discrete ? Space::Discrete(3) : Space::Box(-1.0f, 1.0f, {1});
    spec.env_obs_space = Space::Box(-inf, inf, {2});
    spec.task_obs_space = Space::Box(-1.0f, 1.0f, {1});
    spec.info_fields = {"success", "distance"};
    spec.max_episode_steps = max_steps;
    return spec;
  }

  double target() const { return target_; }

 protected:
  TaskState DoSampleTaskState(Rng& rng) override {
    return TaskState{id(), {{"target", rng.Uniform(-1.0, 1.0)}}};
  }
  TaskState DoGetTaskState() const override { return TaskState{id(), {{"target", target_}}}; }
  void DoSetTaskState(const TaskState& state) override {
    TaskStateReader reader(state, id());
    reader.ExpectKeys({"target"});
    target_ = reader.Number("target", -1.0, 1.0);
    const float obs[1] = {static_cast<float>(target_)};
    SetTaskObs(obs);
  }
  void DoReset(const ObsView& out) override {
    position_ = env_rng().Uniform(-0.1, 0.1);
    velocity_ = 0.0;
    out.env_obs[0] = static_cast<float>(position_);
    out.env_obs[1] = 0.0f;
  }
  void DoStep(std::span<const float> action, const StepView& out) override {
    const double a = discrete_ ? (action[0] - 1.0) : action[0];
    velocity_ = 0.1 * a + 0.01 * env_rng().Normal();
    position_ += velocity_;
    const double distance = std::abs(position_ - target_);
    out.env_obs[0] = static_cast<float>(position_);
    out.env_obs[1] = static_cast<float>(velocity_);
    *out.reward = static_cast<float>(-distance);
    *out.terminated = distance < 0.05;
    out.info[0] = distance < 0.05 ? 1.0f : 0.0f;
    out.info[1] = static_cast<float>(distance);
  }

 private:
  bool discrete_;
  double target_ = 0.0;
  double position_ = 0.0;
  double velocity_ = 0.0;
};

}  // namespace manyworlds::testing

#endif  // MANYWORLDS_TESTS_CORE_TOY_ENV_H_
