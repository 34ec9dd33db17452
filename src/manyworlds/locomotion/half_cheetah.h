// A planar half-cheetah on MuJoCo with the meta-RL task families of MAML,
// ProMP and PEARL (maml_rl's half_cheetah_env_rand.py, ProMP's and oyster's
// half-cheetah envs):
//   half-cheetah-vel  task = target velocity v* ~ U[0, 2] (garage's and
//                     maml_rl's range; oyster's code draws U[0, 3]);
//                     reward = -|v_x - v*| - 0.05 |a|^2;
//   half-cheetah-dir  task = direction d in {-1, +1} (Bernoulli 0.5);
//                     reward = d v_x - 0.05 |a|^2.
// v_x is the torso's x displacement over the control step divided by its
// duration (frame_skip 5 x timestep 0.01 = 0.05 s), as in the sources.
//
// The model is our own MJCF written from the published facts of the
// Gym/MuJoCo half-cheetah: a capsule torso with a head, two legs of thigh,
// shin and foot capsules (their lengths, offsets and angles), joint ranges,
// stiffness and damping, motor gears 120, 90, 60 (back) and 120, 60, 30
// (front), timestep 0.01, floor friction 0.4.
//
//   action:   Box(-1, 1, (6,)): the six motors (ctrl range [-1, 1]).
//   env_obs:  Box(-inf, inf, (17,)): qpos without the root x (8), then qvel (9).
//   task_obs: Box(1,): the target velocity or direction (zeros if hide_task).
//   reset:    qpos = initial + U[-0.1, 0.1], qvel = 0.1 N(0, 1) (Gym's noise).
//   end:      never terminates; truncated after `horizon` steps (default
//             200 for vel, as MAML and PEARL; 100 for dir, as garage).
//   info:     forward_velocity, control_cost.
//   MuJoCo warnings end the episode (truncated, reward 0) and are counted
//   in the info field sim_warnings, or throw with throw_on_sim_warning.
#ifndef MANYWORLDS_LOCOMOTION_HALF_CHEETAH_H_
#define MANYWORLDS_LOCOMOTION_HALF_CHEETAH_H_

#include <cstdint>
#include <string>

#include "manyworlds/core/env.h"
#include "manyworlds/sim/model.h"
#include "manyworlds/sim/scene_source.h"

namespace manyworlds::locomotion {

enum class CheetahTask { kVelocity, kDirection };

class HalfCheetahEnv : public Env, public sim::SceneSource {
 public:
  struct Config {
    CheetahTask task = CheetahTask::kVelocity;
    int64_t horizon = 200;
    bool hide_task = true;
    bool throw_on_sim_warning = false;
  };

  // Throws ConfigError on a bad option, MujocoError if the model fails.
  explicit HalfCheetahEnv(const Config& config);

  // The MJCF of the model (our own; see the top of this file).
  static const std::string& ModelXml();
  const mjModel* model() const { return model_.get(); }
  const mjData* data() const { return data_.get(); }
  double goal() const { return goal_; }

  // SceneSource: the one model (every task shares it) and its data; its
  // MJCF is ModelXml(). Rendered by default from the model's camera "track",
  // which follows the torso from the side.
  sim::Scene ActiveScene() const override { return {model(), data()}; }
  void SaveSceneXml(const std::string& path) const override;
  std::string_view default_camera() const override { return "track"; }

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  static EnvSpec MakeSpec(const Config& config);
  void WriteObs(std::span<float> out) const;

  Config config_;
  sim::ModelPtr model_;
  sim::DataPtr data_;
  double goal_ = 0.0;  // target velocity, or direction
};

}  // namespace manyworlds::locomotion

#endif  // MANYWORLDS_LOCOMOTION_HALF_CHEETAH_H_
