#include "manyworlds/locomotion/half_cheetah.h"

#include <cmath>
#include <string>

#include "manyworlds/core/atomic_file.h"
#include "manyworlds/core/error.h"
#include "manyworlds/sim/warnings.h"

namespace manyworlds::locomotion {
namespace {

constexpr int kFrameSkip = 5;  // control step = 5 x 0.01 s
constexpr double kControlCost = 0.05;
constexpr double kResetNoise = 0.1;
constexpr double kMaxGoalVelocity = 2.0;

const char* IdOf(CheetahTask task) {
  return task == CheetahTask::kVelocity ? "half-cheetah-vel" : "half-cheetah-dir";
}

// Written for manyworlds from the model's published dimensions: capsule
// radius 0.046; each limb capsule given by its centre, half-length and
// pitch; joints with range, stiffness and damping; motor gears.
constexpr char kModelHead[] = R"(<mujoco model="manyworlds_half_cheetah">
  <compiler angle="radian" coordinate="local" inertiafromgeom="true"/>
  <option timestep="0.01" integrator="RK4"/>
  <default>
    <joint limited="true" armature="0.1" damping="0.01" stiffness="8"/>
    <geom type="capsule" size="0.046" condim="3" contype="1" conaffinity="0"
          friction="0.4 0.1 0.1" rgba="0.75 0.6 0.45 1"/>
    <motor ctrllimited="true" ctrlrange="-1 1"/>
  </default>
  <worldbody>
    <light pos="0 0 3" dir="0 0 -1" diffuse="0.8 0.8 0.8"/>
    <geom name="floor" type="plane" size="60 60 2" pos="0 0 0" conaffinity="1"
          rgba="0.35 0.4 0.45 1"/>
    <body name="torso" pos="0 0 0.7">
      <camera name="track" mode="trackcom" pos="0 -3 0.3" xyaxes="1 0 0 0 0 1"/>
      <joint name="rootx" type="slide" axis="1 0 0" limited="false" armature="0" damping="0" stiffness="0"/>
      <joint name="rootz" type="slide" axis="0 0 1" limited="false" armature="0" damping="0" stiffness="0"/>
      <joint name="rooty" type="hinge" axis="0 1 0" limited="false" armature="0" damping="0" stiffness="0"/>
      <geom name="torso" fromto="-0.5 0 0 0.5 0 0"/>
      <geom name="head" pos="0.6 0 0.1" axisangle="0 1 0 0.87" size="0.046 0.15"/>
)";

// One limb segment: a body with its hinge (about y) and its capsule.
struct Segment {
  const char* name;         // of the body, its joint and its capsule
  const char* pos;          // the body in its parent's frame
  const char* range;        // joint range (radians)
  const char* stiffness;
  const char* damping;
  const char* capsule_pos;  // the capsule's centre in the body frame
  const char* pitch;        // the capsule's angle about y (radians)
  const char* half_length;  // of the capsule
};

// Thigh, shin and foot, each the parent of the next.
constexpr Segment kBackLeg[] = {
    {"bthigh", "-0.5 0 0", "-0.52 1.05", "240", "6", "0.1 0 -0.13", "-3.8", "0.145"},
    {"bshin", "0.16 0 -0.25", "-0.785 0.785", "180", "4.5", "-0.14 0 -0.07", "-2.03", "0.15"},
    {"bfoot", "-0.28 0 -0.14", "-0.4 0.785", "120", "3", "0.03 0 -0.097", "-0.27", "0.094"}};
constexpr Segment kFrontLeg[] = {
    {"fthigh", "0.5 0 0", "-1 0.7", "180", "4.5", "-0.07 0 -0.12", "0.52", "0.133"},
    {"fshin", "-0.14 0 -0.24", "-1.2 0.87", "120", "3", "0.065 0 -0.09", "-0.6", "0.106"},
    {"ffoot", "0.13 0 -0.18", "-0.5 0.5", "60", "1.5", "0.045 0 -0.07", "-0.6", "0.07"}};

constexpr char kModelTail[] = R"(    </body>
  </worldbody>
  <actuator>
    <motor name="bthigh" joint="bthigh" gear="120"/>
    <motor name="bshin" joint="bshin" gear="90"/>
    <motor name="bfoot" joint="bfoot" gear="60"/>
    <motor name="fthigh" joint="fthigh" gear="120"/>
    <motor name="fshin" joint="fshin" gear="60"/>
    <motor name="ffoot" joint="ffoot" gear="30"/>
  </actuator>
</mujoco>
)";

// A leg's nested bodies, indented below the torso.
std::string LegXml(const Segment (&leg)[3]) {
  std::string xml;
  for (int i = 0; i < 3; ++i) {
    const std::string indent(6 + 2 * i, ' ');
    const Segment& s = leg[i];
    const std::string name = std::string("name=\"") + s.name + "\"";
    xml += indent + "<body " + name + " pos=\"" + s.pos + "\">\n";
    xml += indent + "  <joint " + name + " type=\"hinge\" axis=\"0 1 0\" range=\"" + s.range +
           "\" stiffness=\"" + s.stiffness + "\" damping=\"" + s.damping + "\"/>\n";
    xml += indent + "  <geom " + name + " pos=\"" + s.capsule_pos + "\" axisangle=\"0 1 0 " +
           s.pitch + "\" size=\"0.046 " + s.half_length + "\"/>\n";
  }
  for (int i = 2; i >= 0; --i) xml += std::string(6 + 2 * i, ' ') + "</body>\n";
  return xml;
}

}  // namespace

const std::string& HalfCheetahEnv::ModelXml() {
  static const std::string xml =
      kModelHead + LegXml(kBackLeg) + LegXml(kFrontLeg) + kModelTail;
  return xml;
}

void HalfCheetahEnv::SaveSceneXml(const std::string& path) const {
  AtomicWriteFile(path, ModelXml());
}

EnvSpec HalfCheetahEnv::MakeSpec(const Config& config) {
  if (config.horizon < 1) {
    throw ConfigError(std::string("env '") + IdOf(config.task) +
                      "': option 'horizon' must be >= 1, got " + std::to_string(config.horizon));
  }
  const float inf = std::numeric_limits<float>::infinity();
  EnvSpec spec;
  spec.id = IdOf(config.task);
  spec.description = config.task == CheetahTask::kVelocity
                         ? "Planar half-cheetah (MuJoCo); task = target forward velocity"
                         : "Planar half-cheetah (MuJoCo); task = run forward or backward";
  spec.action_space = Space::Box(-1.0f, 1.0f, {6});
  spec.env_obs_space = Space::Box(-inf, inf, {17});
  spec.task_obs_space = config.task == CheetahTask::kVelocity
                            ? Space::Box(0.0f, static_cast<float>(kMaxGoalVelocity), {1})
                            : Space::Box(-1.0f, 1.0f, {1});
  spec.info_fields = {"forward_velocity", "control_cost", "sim_warnings"};
  spec.max_episode_steps = config.horizon;
  return spec;
}

HalfCheetahEnv::HalfCheetahEnv(const Config& config)
    : Env(MakeSpec(config)),
      config_(config),
      model_(sim::LoadModelFromString(ModelXml(), {}, "half_cheetah.xml")),
      data_(sim::MakeData(model_.get())) {}

TaskState HalfCheetahEnv::DoSampleTaskState(Rng& task_rng) {
  if (config_.task == CheetahTask::kVelocity) {
    return TaskState{id(), {{"goal_velocity", task_rng.Uniform(0.0, kMaxGoalVelocity)}}};
  }
  return TaskState{id(), {{"direction", task_rng.Bernoulli(0.5) ? 1 : -1}}};
}

TaskState HalfCheetahEnv::DoGetTaskState() const {
  if (config_.task == CheetahTask::kVelocity) return TaskState{id(), {{"goal_velocity", goal_}}};
  return TaskState{id(), {{"direction", static_cast<int>(goal_)}}};
}

void HalfCheetahEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, id());
  if (config_.task == CheetahTask::kVelocity) {
    reader.ExpectKeys({"goal_velocity"});
    goal_ = reader.Number("goal_velocity", 0.0, kMaxGoalVelocity);
  } else {
    reader.ExpectKeys({"direction"});
    const int64_t d = reader.Integer("direction", -1, 1);
    if (d == 0)
      throw TaskStateError("task state for env '" + id() + "': direction must be -1 or +1, got 0");
    goal_ = static_cast<double>(d);
  }
  const float obs = config_.hide_task ? 0.0f : static_cast<float>(goal_);
  SetTaskObs(std::span<const float>(&obs, 1));
}

void HalfCheetahEnv::WriteObs(std::span<float> out) const {
  const mjModel* m = model_.get();
  const mjData* d = data_.get();
  for (int i = 1; i < m->nq; ++i) out[i - 1] = static_cast<float>(d->qpos[i]);
  for (int i = 0; i < m->nv; ++i) out[m->nq - 1 + i] = static_cast<float>(d->qvel[i]);
}

void HalfCheetahEnv::DoReset(const ObsView& out) {
  mjModel* m = model_.get();
  mjData* d = data_.get();
  mj_resetData(m, d);
  Rng& rng = env_rng();
  for (int i = 0; i < m->nq; ++i) d->qpos[i] = m->qpos0[i] + rng.Uniform(-kResetNoise, kResetNoise);
  for (int i = 0; i < m->nv; ++i) d->qvel[i] = kResetNoise * rng.Normal();
  mj_forward(m, d);
  WriteObs(out.env_obs);
}

void HalfCheetahEnv::DoStep(std::span<const float> action, const StepView& out) {
  mjModel* m = model_.get();
  mjData* d = data_.get();
  double control = 0.0;
  for (int i = 0; i < m->nu; ++i) {
    d->ctrl[i] = action[i];
    control += static_cast<double>(action[i]) * action[i];
  }
  const double x_before = d->qpos[0];
  const int warnings = sim::StepAndCheck(m, d, kFrameSkip, config_.throw_on_sim_warning, id());
  const double velocity = (d->qpos[0] - x_before) / (kFrameSkip * m->opt.timestep);
  const double control_cost = kControlCost * control;
  WriteObs(out.env_obs);
  out.info[0] = static_cast<float>(velocity);
  out.info[1] = static_cast<float>(control_cost);
  out.info[2] = static_cast<float>(warnings);
  if (warnings > 0) {  // the state is not to be trusted: end without reward
    *out.reward = 0.0f;
    *out.truncated = true;
    return;
  }
  const double progress =
      config_.task == CheetahTask::kVelocity ? -std::abs(velocity - goal_) : goal_ * velocity;
  *out.reward = static_cast<float>(progress - control_cost);
}

}  // namespace manyworlds::locomotion
