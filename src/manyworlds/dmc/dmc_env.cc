#include "manyworlds/dmc/dmc_env.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "manyworlds/core/atomic_file.h"
#include "manyworlds/core/error.h"
#include "manyworlds/dmc/models.h"
#include "manyworlds/dmc/rewards.h"
#include "manyworlds/sim/warnings.h"

namespace manyworlds::dmc {
namespace {

// MTEnv's variant files, in order (docs/reference/dmc_hipbmdp.md, section 1.2).
constexpr std::array<double, kNumVariants> kFingerSizes = {0.025, 0.05,  0.075, 0.1,   0.125,
                                                           0.15,  0.175, 0.2,   0.225, 0.25};
constexpr std::array<double, kNumVariants> kTorsoHalfLengths = {0.5, 0.6, 0.7, 0.8, 0.9,
                                                                1.0, 1.1, 1.2, 1.3, 1.4};
constexpr std::array<double, kNumVariants> kFrictions = {0.7, 0.8, 0.9, 1.0, 1.1,
                                                         1.2, 1.3, 1.4, 1.5, 1.6};
constexpr std::array<double, kNumVariants> kFootHalfLengths = {0.08, 0.09, 0.10, 0.11, 0.12,
                                                               0.13, 0.14, 0.15, 0.16, 0.17};
// MTRL's finger split (config/env/dmcontrol-finger-spin-distribution-v0.yaml), 0-based.
constexpr std::array<int, 4> kMtrlTrain = {3, 4, 7, 8};
constexpr std::array<int, 2> kMtrlInterpolation = {5, 6};
constexpr std::array<int, 2> kMtrlExtrapolation = {2, 9};

// dm_control's finger redraws its initial pose until nothing touches, at most this often.
constexpr int kMaxInitialPoseDraws = 1000;
// dm_control's cheetah settles for this many physics steps at zero control.
constexpr int kCheetahSettleSteps = 200;

// The finger's sensordata layout (models.cc's <sensor> order).
constexpr int kFingerProximal = 0, kFingerDistal = 1, kFingerVelocities = 2,
              kFingerHingeVelocity = 4, kFingerTip = 5, kFingerSpinner = 8, kFingerTouch = 11;
// The walker's bodies after the world: torso, then the legs.
constexpr int kWalkerTorso = 1, kWalkerBodies = 7;

int ObsSize(DmcTask task) {
  switch (task) {
    case DmcTask::kFingerSpin:
      return 9;
    case DmcTask::kCheetahRun:
      return 17;
    case DmcTask::kWalkerWalk:
      return 24;
  }
  return 0;
}

int Substeps(DmcTask task) {
  switch (task) {
    case DmcTask::kFingerSpin:
      return 2;  // 0.02 s control step / 0.01 s
    case DmcTask::kCheetahRun:
      return 1;  // no control step given: one physics step
    case DmcTask::kWalkerWalk:
      return 10;  // 0.025 s / 0.0025 s
  }
  return 1;
}

const char* ParameterName(Variation variation) {
  switch (variation) {
    case Variation::kFingerSize:
      return "touch_site_x";
    case Variation::kCheetahTorsoLength:
      return "torso_half_length";
    case Variation::kWalkerFriction:
      return "friction";
    case Variation::kWalkerFootLength:
      return "left_foot_half_length";
    case Variation::kNone:
      break;
  }
  return "";
}

std::string FormatValue(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%g", x);
  return buffer;
}

std::string ModelXmlFor(DmcTask task, Variation variation, int variant) {
  const double value = variation == Variation::kNone ? 0.0 : VariantValues(variation)[variant];
  switch (variation) {
    case Variation::kFingerSize:
      return FingerXml({.touch_site_x = value});
    case Variation::kCheetahTorsoLength:
      return CheetahXml({.torso_half_length = value});
    case Variation::kWalkerFriction:
      return WalkerXml({.friction = value});
    case Variation::kWalkerFootLength:
      return WalkerXml({.left_foot_half_length = value});
    case Variation::kNone:
      break;
  }
  switch (task) {
    case DmcTask::kFingerSpin:
      return FingerXml();
    case DmcTask::kCheetahRun:
      return CheetahXml();
    case DmcTask::kWalkerWalk:
      return WalkerXml();
  }
  return "";
}

// Whether data made for `a` is laid out as `b` needs it (the counts mj_makeData sizes by).
bool SameDataLayout(const mjModel* a, const mjModel* b) {
  return a->nq == b->nq && a->nv == b->nv && a->nu == b->nu && a->na == b->na &&
         a->nbody == b->nbody && a->njnt == b->njnt && a->ngeom == b->ngeom &&
         a->nsite == b->nsite && a->ncam == b->ncam && a->nlight == b->nlight &&
         a->ntendon == b->ntendon && a->nwrap == b->nwrap && a->nmocap == b->nmocap &&
         a->nsensordata == b->nsensordata && a->nuserdata == b->nuserdata &&
         a->nconmax == b->nconmax && a->njmax == b->njmax && a->nstack == b->nstack &&
         a->nM == b->nM;
}

// dm_control's joint randomiser: a limited hinge or slide uniform in its range; with
// `free_hinges`, an unlimited hinge uniform in [-pi, pi]; anything else stays.
void RandomizeJoints(const mjModel* m, mjData* d, Rng& rng, bool free_hinges) {
  for (int j = 0; j < m->njnt; ++j) {
    const int type = m->jnt_type[j];
    if (type != mjJNT_HINGE && type != mjJNT_SLIDE) continue;
    double& q = d->qpos[m->jnt_qposadr[j]];
    if (m->jnt_limited[j]) {
      q = rng.Uniform(m->jnt_range[2 * j], m->jnt_range[2 * j + 1]);
    } else if (free_hinges && type == mjJNT_HINGE) {
      q = rng.Uniform(-std::numbers::pi, std::numbers::pi);
    }
  }
}

}  // namespace

std::span<const double> VariantValues(Variation variation) {
  switch (variation) {
    case Variation::kFingerSize:
      return kFingerSizes;
    case Variation::kCheetahTorsoLength:
      return kTorsoHalfLengths;
    case Variation::kWalkerFriction:
      return kFrictions;
    case Variation::kWalkerFootLength:
      return kFootHalfLengths;
    case Variation::kNone:
      break;
  }
  return {};
}

DmcTask TaskOf(Variation variation) {
  switch (variation) {
    case Variation::kCheetahTorsoLength:
      return DmcTask::kCheetahRun;
    case Variation::kWalkerFriction:
    case Variation::kWalkerFootLength:
      return DmcTask::kWalkerWalk;
    case Variation::kFingerSize:
    case Variation::kNone:
      break;
  }
  return DmcTask::kFingerSpin;
}

std::span<const int> MtrlTrainVariants() { return kMtrlTrain; }
std::span<const int> MtrlInterpolationVariants() { return kMtrlInterpolation; }
std::span<const int> MtrlExtrapolationVariants() { return kMtrlExtrapolation; }

std::string DmcEnv::IdOf(DmcTask task, Variation variation) {
  switch (variation) {
    case Variation::kFingerSize:
      return "hipbmdp-finger-spin-size";
    case Variation::kCheetahTorsoLength:
      return "hipbmdp-cheetah-run-torso-length";
    case Variation::kWalkerFriction:
      return "hipbmdp-walker-walk-friction";
    case Variation::kWalkerFootLength:
      return "hipbmdp-walker-walk-foot-length";
    case Variation::kNone:
      break;
  }
  switch (task) {
    case DmcTask::kFingerSpin:
      return "dmc-finger-spin";
    case DmcTask::kCheetahRun:
      return "dmc-cheetah-run";
    case DmcTask::kWalkerWalk:
      return "dmc-walker-walk";
  }
  return "";
}

std::string DmcEnv::Description(DmcTask task, Variation variation) {
  std::string text;
  switch (task) {
    case DmcTask::kFingerSpin:
      text = "Planar finger spinning a hinged body";
      break;
    case DmcTask::kCheetahRun:
      text = "Planar cheetah running forward";
      break;
    case DmcTask::kWalkerWalk:
      text = "Planar biped walking forward";
      break;
  }
  text += " (MuJoCo, dm_control's task)";
  if (variation != Variation::kNone) {
    text += "; task = one of 10 " + std::string(ParameterName(variation)) +
            " variants (MTEnv HiP-BMDP)";
  }
  return text;
}

EnvSpec DmcEnv::MakeSpec(const Config& config) {
  const std::string id = IdOf(config.task, config.variation);
  if (config.variation != Variation::kNone && TaskOf(config.variation) != config.task) {
    throw ConfigError("env '" + id + "': the variation belongs to another task");
  }
  if (config.split == Split::kMtrl && config.variation != Variation::kFingerSize) {
    throw ConfigError("env '" + id +
                      "': option 'split' must be 'all'; 'mtrl' exists only for "
                      "hipbmdp-finger-spin-size");
  }
  if (config.horizon < 1) {
    throw ConfigError("env '" + id + "': horizon must be >= 1, got " +
                      std::to_string(config.horizon));
  }
  const float inf = std::numeric_limits<float>::infinity();
  EnvSpec spec;
  spec.id = id;
  spec.description = Description(config.task, config.variation);
  switch (config.task) {
    case DmcTask::kFingerSpin:
      spec.info_fields = {"hinge_velocity", "sim_warnings"};
      break;
    case DmcTask::kCheetahRun:
      spec.info_fields = {"com_velocity", "sim_warnings"};
      break;
    case DmcTask::kWalkerWalk:
      spec.info_fields = {"torso_height", "torso_upright", "com_velocity", "sim_warnings"};
      break;
  }
  if (config.variation != Variation::kNone) spec.task_obs_space = Space::Discrete(kNumVariants);
  spec.action_space = Space::Box(-1.0f, 1.0f, {config.task == DmcTask::kFingerSpin ? 2 : 6});
  spec.env_obs_space = Space::Box(-inf, inf, {ObsSize(config.task)});
  spec.max_episode_steps = config.horizon;
  return spec;
}

DmcEnv::DmcEnv(const Config& config)
    : Env(MakeSpec(config)), config_(config), substeps_(Substeps(config.task)) {
  UseVariant(0);
}

void DmcEnv::UseVariant(int variant) {
  const CompiledMjcf*& entry = compiled_[variant];
  if (entry == nullptr) {
    entry = &CompiledModel(ModelXmlFor(config_.task, config_.variation, variant), id() + ".xml");
  }
  variant_ = variant;
  if (entry == current_) return;
  const mjModel* m = entry->model.get();
  // Variants differ only in numbers, so the data of one fits another: no reallocation.
  if (!data_ || !SameDataLayout(current_->model.get(), m)) data_ = sim::MakeData(m);
  current_ = entry;
  mj_forward(m, data_.get());  // the scene as the new model shows it; Reset starts afresh
}

void DmcEnv::SetPhysicsState(std::span<const double> qpos, std::span<const double> qvel) {
  const mjModel* m = model();
  mjData* d = data_.get();
  if (qpos.size() != static_cast<size_t>(m->nq) || qvel.size() != static_cast<size_t>(m->nv)) {
    throw Error("env '" + id() + "': a physics state has " + std::to_string(m->nq) +
                " positions and " + std::to_string(m->nv) + " velocities, got " +
                std::to_string(qpos.size()) + " and " + std::to_string(qvel.size()));
  }
  std::copy(qpos.begin(), qpos.end(), d->qpos);
  std::copy(qvel.begin(), qvel.end(), d->qvel);
  mj_forward(m, d);
}

void DmcEnv::SaveSceneXml(const std::string& path) const {
  AtomicWriteFile(path, current_->xml);
}

std::string_view DmcEnv::default_camera() const {
  return config_.task == DmcTask::kFingerSpin ? "fixed" : "side";
}

std::vector<TaskGroup> DmcEnv::EvaluationTasks() const {
  if (config_.variation == Variation::kNone) return {};
  auto state = [&](int k) { return TaskState{id(), {{"variant", k}}}; };
  std::vector<TaskGroup> groups;
  if (config_.split == Split::kMtrl) {
    const std::pair<const char*, std::span<const int>> sets[] = {
        {"train", kMtrlTrain},
        {"interpolation", kMtrlInterpolation},
        {"extrapolation", kMtrlExtrapolation}};
    for (const auto& [name, variants] : sets) {
      TaskGroup group{name, {}};
      for (const int k : variants) group.states.push_back(state(k));
      groups.push_back(std::move(group));
    }
    return groups;
  }
  const auto values = VariantValues(config_.variation);
  for (int k = 0; k < kNumVariants; ++k) {
    groups.push_back(TaskGroup{
        std::string(ParameterName(config_.variation)) + "=" + FormatValue(values[k]), {state(k)}});
  }
  return groups;
}

TaskState DmcEnv::DoSampleTaskState(Rng& task_rng) {
  if (config_.variation == Variation::kNone) return TaskState{id(), nlohmann::json::object()};
  int k = 0;
  if (config_.split == Split::kMtrl) {
    k = kMtrlTrain[task_rng.UniformInt(kMtrlTrain.size())];
  } else {
    k = static_cast<int>(task_rng.UniformInt(kNumVariants));
  }
  return TaskState{id(), {{"variant", k}}};
}

TaskState DmcEnv::DoGetTaskState() const {
  if (config_.variation == Variation::kNone) return TaskState{id(), nlohmann::json::object()};
  return TaskState{id(), {{"variant", variant_}}};
}

void DmcEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, id());
  if (config_.variation == Variation::kNone) {
    reader.ExpectKeys({});
    SetTaskObs({});
    return;
  }
  reader.ExpectKeys({"variant"});
  const int k = static_cast<int>(reader.Integer("variant", 0, kNumVariants - 1));
  UseVariant(k);
  const float obs = static_cast<float>(k);
  SetTaskObs(std::span<const float>(&obs, 1));
}

void DmcEnv::InitializeEpisode() {
  const mjModel* m = model();
  mjData* d = data_.get();
  Rng& rng = env_rng();
  switch (config_.task) {
    case DmcTask::kFingerSpin:
      for (int draw = 0; draw < kMaxInitialPoseDraws; ++draw) {
        RandomizeJoints(m, d, rng, /*free_hinges=*/true);
        mj_forward(m, d);
        if (d->ncon == 0) return;
      }
      throw Error("env '" + id() + "': no contact-free initial pose in " +
                  std::to_string(kMaxInitialPoseDraws) + " draws");
    case DmcTask::kCheetahRun:
      RandomizeJoints(m, d, rng, /*free_hinges=*/false);
      // As dm_control's legacy stepping does it: the first step finishes from the positions
      // of the reset pose, the last recomputes positions and velocities.
      mj_step2(m, d);
      for (int i = 1; i < kCheetahSettleSteps; ++i) mj_step(m, d);
      mj_step1(m, d);
      d->time = 0.0;
      return;
    case DmcTask::kWalkerWalk:
      RandomizeJoints(m, d, rng, /*free_hinges=*/true);
      return;
  }
}

void DmcEnv::DoReset(const ObsView& out) {
  const mjModel* m = model();
  mjData* d = data_.get();
  mj_resetData(m, d);
  mj_forward(m, d);
  InitializeEpisode();
  mj_forward(m, d);
  WriteObs(out.env_obs);
}

int DmcEnv::ControlStep() {
  const mjModel* m = model();
  mjData* d = data_.get();
  const int before = sim::WarningTotal(d);
  // dm_control's legacy stepping: positions and velocities are up to date after every
  // control step, so the first substep only finishes (mj_step2) and the last is followed by
  // mj_step1.
  mj_step2(m, d);
  for (int i = 1; i < substeps_; ++i) mj_step(m, d);
  mj_step1(m, d);
  const int warnings = sim::WarningTotal(d) - before;
  if (warnings > 0 && config_.throw_on_sim_warning) sim::ThrowIfWarnings(d, id());
  return warnings;
}

void DmcEnv::DoStep(std::span<const float> action, const StepView& out) {
  const mjModel* m = model();
  mjData* d = data_.get();
  for (int i = 0; i < m->nu; ++i) d->ctrl[i] = action[i];
  const int warnings = ControlStep();
  WriteObs(out.env_obs);
  const double reward = RewardAndInfo(out.info);
  out.info[out.info.size() - 1] = static_cast<float>(warnings);
  if (warnings > 0) {  // the state is not to be trusted: end without reward
    *out.reward = 0.0f;
    *out.truncated = true;
    return;
  }
  *out.reward = static_cast<float>(reward);
}

void DmcEnv::WriteObs(std::span<float> out) const {
  const mjModel* m = model();
  const mjData* d = data_.get();
  const mjtNum* s = d->sensordata;
  size_t n = 0;
  auto put = [&](double x) { out[n++] = static_cast<float>(x); };
  switch (config_.task) {
    case DmcTask::kFingerSpin:
      put(s[kFingerProximal]);
      put(s[kFingerDistal]);
      put(s[kFingerTip] - s[kFingerSpinner]);          // x
      put(s[kFingerTip + 2] - s[kFingerSpinner + 2]);  // z
      for (int i = 0; i < 3; ++i) put(s[kFingerVelocities + i]);
      for (int i = 0; i < 2; ++i) put(std::log1p(s[kFingerTouch + i]));
      break;
    case DmcTask::kCheetahRun:
      for (int i = 1; i < m->nq; ++i) put(d->qpos[i]);
      for (int i = 0; i < m->nv; ++i) put(d->qvel[i]);
      break;
    case DmcTask::kWalkerWalk:
      for (int b = 1; b <= kWalkerBodies; ++b) {
        put(d->xmat[9 * b]);      // xx
        put(d->xmat[9 * b + 2]);  // xz
      }
      put(d->xpos[3 * kWalkerTorso + 2]);
      for (int i = 0; i < m->nv; ++i) put(d->qvel[i]);
      break;
  }
}

double DmcEnv::RewardAndInfo(std::span<float> info) const {
  const mjData* d = data_.get();
  switch (config_.task) {
    case DmcTask::kFingerSpin: {
      const double hinge_velocity = d->sensordata[kFingerHingeVelocity];
      info[0] = static_cast<float>(hinge_velocity);
      return FingerSpinReward(hinge_velocity);
    }
    case DmcTask::kCheetahRun: {
      const double velocity = d->sensordata[0];
      info[0] = static_cast<float>(velocity);
      return CheetahRunReward(velocity);
    }
    case DmcTask::kWalkerWalk: {
      const double height = d->xpos[3 * kWalkerTorso + 2];
      const double upright = d->xmat[9 * kWalkerTorso + 8];
      const double velocity = d->sensordata[0];
      info[0] = static_cast<float>(height);
      info[1] = static_cast<float>(upright);
      info[2] = static_cast<float>(velocity);
      return WalkerWalkReward(height, upright, velocity);
    }
  }
  return 0.0;
}

}  // namespace manyworlds::dmc
