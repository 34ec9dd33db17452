// DeepMind-Control-style tasks on our own MuJoCo models (dmc/models.h), with dm_control's
// semantics (docs/reference/dmc_hipbmdp.md):
//
//   task         control step               obs  reward (dmc/rewards.h)
//   finger-spin  2 x 0.01 s    (0.02 s)      9   1 if the spinner turns at <= -15 rad/s
//   cheetah-run  1 x 0.01 s    (0.01 s)     17   centre-of-mass x velocity / 10, clipped to [0, 1]
//   walker-walk  10 x 0.0025 s (0.025 s)    24   standing x upright x moving at >= 1 m/s
//
// Episodes are 1000 control steps (dm_control's 20 s, 10 s and 25 s), truncated there; no
// task terminates. Actions are the motors' controls, Box(-1, 1). Observations, in dm_control's
// order (its flattened state observation):
//   finger   proximal and distal angles, tip (x, z) relative to the spinner's origin,
//            proximal, distal and spinner velocities, log(1 + touch) of the two fingertip
//            touch sensors (top, bottom);
//   cheetah  qpos without the root x (8), qvel (9);
//   walker   rotation-matrix entries xx and xz of the 7 bodies (torso, right thigh, leg,
//            foot, left thigh, leg, foot), torso height, qvel (9).
// Initial states, as dm_control draws them (with our generator, so not its numbers):
//   finger   both finger joints uniform in their range, spinner uniform in [-pi, pi],
//            redrawn until nothing touches; velocities 0;
//   cheetah  the six leg joints uniform in their ranges, then 200 physics steps (2 s) at zero
//            control to settle;
//   walker   torso pitch uniform in [-pi, pi], the six leg joints uniform in their ranges,
//            torso origin at 1.3 m; no settling (it falls from there).
// A control step follows dm_control's legacy stepping: the substeps, then positions,
// velocities and sensors recomputed for the new state, which reward and observation read.
//
// The HiP-BMDP multi-task envs (MTEnv's four ids) vary one physical parameter over 10
// variants; task state {"variant": k} with k in [0, 10) (MTEnv's 0-based index: its file
// _<k+1>); task observation the index k (Discrete(10)), as MTEnv gives it:
//   finger size          touch-site first semi-axis 0.025 (k + 1)
//   cheetah torso length torso half-length 0.5 + 0.1 k
//   walker friction      sliding friction 0.7 + 0.1 k (floor and body)
//   walker foot length   left foot half-length 0.08 + 0.01 k
// Single-task envs have the task state {} and no task observation. Each variant's model is
// compiled once per process (CompiledModel, dmc/models.h) and shared; switching variants keeps
// the env's mjData (same layout), so SetTaskState costs microseconds after a variant's first use.
//
// info: the quantities the reward reads (finger: hinge_velocity; cheetah: com_velocity;
// walker: torso_height, torso_upright, com_velocity) and sim_warnings. MuJoCo warnings end
// the episode (truncated, reward 0), or throw with throw_on_sim_warning.
#ifndef MANYWORLDS_DMC_DMC_ENV_H_
#define MANYWORLDS_DMC_DMC_ENV_H_

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "manyworlds/core/env.h"
#include "manyworlds/dmc/models.h"
#include "manyworlds/sim/model.h"
#include "manyworlds/sim/scene_source.h"

namespace manyworlds::dmc {

enum class DmcTask { kFingerSpin, kCheetahRun, kWalkerWalk };

// What a multi-task env varies; kNone: the single-task env.
enum class Variation {
  kNone,
  kFingerSize,
  kCheetahTorsoLength,
  kWalkerFriction,
  kWalkerFootLength
};

// Which variants a multi-task env samples and evaluates. kMtrl (finger size only): MTRL's
// split, train on variants {3, 4, 7, 8}, evaluate them and the interpolation {5, 6} and
// extrapolation {2, 9} variants.
enum class Split { kAll, kMtrl };

inline constexpr int kNumVariants = 10;
inline constexpr int64_t kEpisodeSteps = 1000;

// The parameter value of each variant, index k = MTEnv's task state k.
std::span<const double> VariantValues(Variation variation);
DmcTask TaskOf(Variation variation);
// The variants MTRL trains on, and its two evaluation sets (finger size).
std::span<const int> MtrlTrainVariants();
std::span<const int> MtrlInterpolationVariants();
std::span<const int> MtrlExtrapolationVariants();

class DmcEnv : public Env, public sim::SceneSource {
 public:
  struct Config {
    DmcTask task = DmcTask::kFingerSpin;
    Variation variation = Variation::kNone;  // must belong to `task`
    Split split = Split::kAll;               // kMtrl only with kFingerSize
    int64_t horizon = kEpisodeSteps;
    bool throw_on_sim_warning = false;
  };

  // Throws ConfigError on a bad config, MujocoError if a model fails.
  explicit DmcEnv(const Config& config);

  static std::string IdOf(DmcTask task, Variation variation);
  static std::string Description(DmcTask task, Variation variation);

  const mjModel* model() const { return current_->model.get(); }
  const mjData* data() const { return data_.get(); }
  int variant() const { return variant_; }
  // The MJCF of the current model.
  const std::string& model_xml() const { return current_->xml; }
  // Overwrites the running episode's positions and velocities (nq and nv values) and
  // recomputes what derives from them, e.g. to start from dm_control's recorded initial state
  // (tests/dmc/physics_replay_test.cc). Throws Error on a wrong size.
  void SetPhysicsState(std::span<const double> qpos, std::span<const double> qvel);

  // SceneSource: the current variant's model; rendered by default from the model's first
  // camera, which mirrors dm_control's camera 0.
  sim::Scene ActiveScene() const override { return {model(), data()}; }
  void SaveSceneXml(const std::string& path) const override;
  std::string_view default_camera() const override;

  // Multi-task: with split kAll one group per variant; with kMtrl the groups "train",
  // "interpolation" and "extrapolation". Single-task: none.
  std::vector<TaskGroup> EvaluationTasks() const override;

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  static EnvSpec MakeSpec(const Config& config);
  void UseVariant(int variant);
  void InitializeEpisode();
  // One control step of legacy stepping; returns the new MuJoCo warnings.
  int ControlStep();
  void WriteObs(std::span<float> out) const;
  // Writes the info fields and returns the reward.
  double RewardAndInfo(std::span<float> info) const;

  Config config_;
  int substeps_ = 1;
  int variant_ = 0;
  // Each variant's document and model, looked up in the process-wide cache on first use.
  std::array<const CompiledMjcf*, kNumVariants> compiled_{};
  const CompiledMjcf* current_ = nullptr;
  sim::DataPtr data_;
};

}  // namespace manyworlds::dmc

#endif  // MANYWORLDS_DMC_DMC_ENV_H_
