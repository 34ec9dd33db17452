// TaskVectorEnv: what the multi-task control envs after MTEnv (MTCartPole,
// MTAcrobot) share. The task is a vector mu in [-1, 1]^5 that sets the
// physical constants:
//   task state params: {"mu": [5 numbers in [-1, 1]]}, drawn U[-1, 1].
//   task_obs: mu, Box(-1, 1, (5,)) (zeros if hide_task).
//   state:    four numbers, drawn U(-reset_noise, reset_noise) at reset
//             from the env generator.
//   info:     success (each env says when).
//   options:  horizon (int, 500, >= 1), hide_task (bool, false).
// A derived env gives its Physics, the map from mu to it, its observation
// of the state and its step.
#ifndef MANYWORLDS_CLASSIC_TASK_VECTOR_ENV_H_
#define MANYWORLDS_CLASSIC_TASK_VECTOR_ENV_H_

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "manyworlds/classic/common.h"
#include "manyworlds/core/env.h"

namespace manyworlds::classic {

template <typename Physics>
class TaskVectorEnv : public Env {
 public:
  static constexpr int kTaskDim = 5;
  using TaskVector = std::array<double, kTaskDim>;
  using State = std::array<double, 4>;

  struct Config {
    int64_t horizon = 500;
    bool hide_task = false;
  };

  const Physics& physics() const { return physics_; }
  const State& state() const { return state_; }

 protected:
  using PhysicsFromMuFn = Physics (*)(const TaskVector& mu);

  // The spec, with the shared task observation, info "success" and
  // horizon. Throws ConfigError on a horizon below 1.
  static EnvSpec MakeSpec(const char* id, const Config& config, const char* description,
                          Space action_space, Space env_obs_space) {
    CheckIntOption(id, "horizon", config.horizon, 1);
    EnvSpec spec;
    spec.id = id;
    spec.description = description;
    spec.action_space = std::move(action_space);
    spec.env_obs_space = std::move(env_obs_space);
    spec.task_obs_space = Space::Box(-1.0f, 1.0f, {kTaskDim});
    spec.info_fields = {"success"};
    spec.max_episode_steps = config.horizon;
    return spec;
  }

  TaskVectorEnv(EnvSpec spec, const Config& config, PhysicsFromMuFn physics_from_mu,
                double reset_noise)
      : Env(std::move(spec)),
        hide_task_(config.hide_task),
        physics_from_mu_(physics_from_mu),
        reset_noise_(reset_noise) {}

  // The observation of state_.
  virtual void WriteObs(std::span<float> env_obs) const = 0;

  TaskState DoSampleTaskState(Rng& task_rng) final {
    std::vector<double> mu(kTaskDim);
    for (double& m : mu) m = task_rng.Uniform(-1.0, 1.0);
    return TaskState{id(), {{"mu", mu}}};
  }

  TaskState DoGetTaskState() const final {
    return TaskState{id(), {{"mu", std::vector<double>(mu_.begin(), mu_.end())}}};
  }

  void DoSetTaskState(const TaskState& state) final {
    TaskStateReader reader(state, id());
    reader.ExpectKeys({"mu"});
    const auto mu = reader.Numbers("mu", kTaskDim, -1.0, 1.0);
    std::copy(mu.begin(), mu.end(), mu_.begin());
    physics_ = physics_from_mu_(mu_);
    float obs[kTaskDim] = {};
    for (int i = 0; i < kTaskDim; ++i) obs[i] = hide_task_ ? 0.0f : static_cast<float>(mu_[i]);
    SetTaskObs(obs);
  }

  void DoReset(const ObsView& out) final {
    for (double& v : state_) v = env_rng().Uniform(-reset_noise_, reset_noise_);
    WriteObs(out.env_obs);
  }

  State state_{};

 private:
  bool hide_task_;
  PhysicsFromMuFn physics_from_mu_;
  double reset_noise_;
  TaskVector mu_{};
  Physics physics_;
};

}  // namespace manyworlds::classic

#endif  // MANYWORLDS_CLASSIC_TASK_VECTOR_ENV_H_
