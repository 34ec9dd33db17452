#include "manyworlds/manipulation/sawyer_task.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "manyworlds/core/error.h"
#include "manyworlds/manipulation/assets.h"
#include "manyworlds/sim/ids.h"
#include "manyworlds/sim/warnings.h"

namespace manyworlds::manipulation {
namespace {

const char* const kArmJoints[7] = {"arm_j0", "arm_j1", "arm_j2", "arm_j3",
                                   "arm_j4", "arm_j5", "arm_j6"};
// Joint angles that put the hand near (0, 0.6, 0.2) pointing down, so the
// settle phase starts close to its end (planar two-link IK for the arm in
// sawyer_arena.xml).
constexpr double kArmHome[7] = {0.0, 0.502, 0.0, 2.342, 0.0, 0.297, 0.0};
constexpr int kSettleSubsteps = 50 * kFrameSkip;

// Observation bounds of the hand (v3's SawyerXYZEnv._HAND_SPACE).
constexpr float kHandSpaceLow[3] = {-0.525f, 0.348f, -0.0525f};
constexpr float kHandSpaceHigh[3] = {0.525f, 1.025f, 0.7f};

Vec3 ToVec3(const mjtNum* p) { return {p[0], p[1], p[2]}; }

std::vector<double> ToVector(const Vec3& v) { return {v[0], v[1], v[2]}; }

double XyDistance(const Vec3& a, const Vec3& b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }

}  // namespace

SawyerTaskConfig TaskConfig(std::string id, std::string description, std::string xml_file,
                            const Range3& obj, const Range3& goal) {
  SawyerTaskConfig config;
  config.id = std::move(id);
  config.description = std::move(description);
  config.xml_file = std::move(xml_file);
  config.obj_low = obj.low;
  config.obj_high = obj.high;
  config.goal_low = goal.low;
  config.goal_high = goal.high;
  return config;
}

EnvSpec SawyerTask::MakeSpec(const SawyerTaskConfig& config, const SawyerOptions& options) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> low(kObsSize, -inf), high(kObsSize, inf);
  for (int frame = 0; frame < 2; ++frame) {
    const int base = frame * kObsFrame;
    for (int i = 0; i < 3; ++i) {
      low[base + kObsHand + i] = kHandSpaceLow[i];
      high[base + kObsHand + i] = kHandSpaceHigh[i];
    }
    low[base + kObsGripper] = -1.0f;
    high[base + kObsGripper] = 1.0f;
  }
  // The goal's bounds: v3's goal_space (config.goal_space) where it is not the goal range.
  const Range3 goal_space = config.goal_space.value_or(Range3{config.goal_low, config.goal_high});
  for (int i = 0; i < 3; ++i) {
    low[kObsGoal + i] = options.goal_observable ? static_cast<float>(goal_space.low[i]) : 0.0f;
    high[kObsGoal + i] = options.goal_observable ? static_cast<float>(goal_space.high[i]) : 0.0f;
  }
  EnvSpec spec;
  spec.id = config.id;
  spec.description = config.description;
  spec.action_space = Space::Box(-1.0f, 1.0f, {4});
  spec.env_obs_space = Space::Box(std::move(low), std::move(high), {kObsSize});
  if (options.goal_observable) {
    std::vector<float> goal_low(3), goal_high(3);
    for (int i = 0; i < 3; ++i) {
      goal_low[i] = static_cast<float>(goal_space.low[i]);
      goal_high[i] = static_cast<float>(goal_space.high[i]);
    }
    spec.task_obs_space = Space::Box(std::move(goal_low), std::move(goal_high), {3});
  }
  spec.info_fields = {"success",         "near_object",   "grasp_success",  "grasp_reward",
                      "in_place_reward", "obj_to_target", "unscaled_reward"};
  spec.max_episode_steps = kMaxEpisodeSteps;
  spec.uses_env_seed = false;  // everything random is in the task state
  return spec;
}

SawyerTask::SawyerTask(SawyerTaskConfig config, SawyerOptions options)
    : Env(MakeSpec(config, options)), config_(std::move(config)), options_(options) {
  model_ = LoadTaskModel(config_.xml_file);
  data_ = sim::MakeData(model_.get());
  const sim::IdLookup ids(model_.get(), config_.xml_file);
  hand_site_ = ids.Site("hand_site");
  left_pad_site_ = ids.Site("left_pad_site");
  right_pad_site_ = ids.Site("right_pad_site");
  obj_body_ = ids.Body("obj");
  obj_geom_ = ids.Geom("obj_geom");
  obj_quat_body_ = config_.obj_quat_body.empty() ? obj_body_ : ids.Body(config_.obj_quat_body);
  left_pad_geom_ = ids.Geom("left_pad");
  right_pad_geom_ = ids.Geom("right_pad");
  // "obj" is a free body in the pick-and-place family, a part of a fixture
  // (a handle, a button) elsewhere.
  const int obj_joint = model_->body_jntadr[obj_body_];
  if (obj_joint >= 0 && model_->jnt_type[obj_joint] == mjJNT_FREE) {
    obj_qpos_ = model_->jnt_qposadr[obj_joint];
    obj_dof_ = model_->jnt_dofadr[obj_joint];
  }
  hand_mocap_ = ids.MocapIndex("hand_mocap");
  goal_mocap_ = ids.MocapIndex("goal");
  left_act_ = ids.Actuator("left_finger_act");
  right_act_ = ids.Actuator("right_finger_act");
  int arm_qpos[7];
  for (int i = 0; i < 7; ++i) arm_qpos[i] = ids.QposAddress(kArmJoints[i]);

  // Settle once: hold the mocap at the hand start with the gripper open.
  mjModel* m = model_.get();
  mjData* d = data_.get();
  mj_resetData(m, d);
  for (int i = 0; i < 7; ++i) d->qpos[arm_qpos[i]] = kArmHome[i];
  for (int i = 0; i < 3; ++i) d->mocap_pos[3 * hand_mocap_ + i] = config_.hand_init[i];
  const mjtNum identity[4] = {1, 0, 0, 0};
  mju_copy4(d->mocap_quat + 4 * hand_mocap_, identity);
  d->ctrl[left_act_] = -1;
  d->ctrl[right_act_] = -1;
  sim::StepAndCheck(m, d, kSettleSubsteps, /*throw_on_warning=*/true,
                    config_.id + ": settling the hand");
  sim::GetState(m, d, &settled_);
  settled_.time = 0;
  state_.hand_init = config_.hand_init;
}

TaskState SawyerTask::DoSampleTaskState(Rng& rng) {
  Vec3 obj{}, goal{};
  // Rejection sampling as in the reference: redraw both until the object and
  // goal are far enough apart in xy.
  do {
    for (int i = 0; i < 3; ++i) obj[i] = rng.Uniform(config_.obj_low[i], config_.obj_high[i]);
    for (int i = 0; i < 3; ++i) goal[i] = rng.Uniform(config_.goal_low[i], config_.goal_high[i]);
    goal = DeriveGoal(obj, goal);
  } while (XyDistance(obj, goal) < config_.min_obj_goal_xy);
  return TaskState{id(), {{"obj_pos", ToVector(obj)}, {"goal_pos", ToVector(goal)}}};
}

TaskState SawyerTask::DoGetTaskState() const {
  return TaskState{id(), {{"obj_pos", ToVector(obj_pos_)}, {"goal_pos", ToVector(goal_pos_)}}};
}

void SawyerTask::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, id());
  reader.ExpectKeys({"obj_pos", "goal_pos"});
  // Numbers() checks one range for all components; the per-axis ranges are
  // checked below.
  const std::vector<double> o = reader.Numbers("obj_pos", 3, -10.0, 10.0);
  const std::vector<double> g = reader.Numbers("goal_pos", 3, -10.0, 10.0);
  const Vec3 obj{o[0], o[1], o[2]};
  const Vec3 goal{g[0], g[1], g[2]};
  const char* axes = "xyz";
  for (int i = 0; i < 3; ++i) {
    const double goal_low = config_.goal_z_at_object && i == 2 ? config_.obj_low[2] : config_.goal_low[i];
    const double goal_high = config_.goal_z_at_object && i == 2 ? config_.obj_high[2] : config_.goal_high[i];
    if (obj[i] < config_.obj_low[i] || obj[i] > config_.obj_high[i]) {
      throw TaskStateError("env '" + id() + "': obj_pos." + axes[i] + " = " +
                           std::to_string(obj[i]) + " outside [" +
                           std::to_string(config_.obj_low[i]) + ", " +
                           std::to_string(config_.obj_high[i]) + "]");
    }
    if (goal[i] < goal_low || goal[i] > goal_high) {
      throw TaskStateError("env '" + id() + "': goal_pos." + axes[i] + " = " +
                           std::to_string(goal[i]) + " outside [" + std::to_string(goal_low) +
                           ", " + std::to_string(goal_high) + "]");
    }
  }
  const Vec3 derived = DeriveGoal(obj, goal);
  if (Distance(derived, goal) > 1e-9) {
    throw TaskStateError("env '" + id() + "': goal_pos is determined by obj_pos in this task; for this obj_pos it must be [" +
                         std::to_string(derived[0]) + ", " + std::to_string(derived[1]) + ", " +
                         std::to_string(derived[2]) + "]");
  }
  if (XyDistance(obj, goal) < config_.min_obj_goal_xy) {
    throw TaskStateError("env '" + id() + "': obj_pos and goal_pos are " +
                         std::to_string(XyDistance(obj, goal)) + " m apart in xy, need >= " +
                         std::to_string(config_.min_obj_goal_xy));
  }
  obj_pos_ = obj;
  goal_pos_ = goal;
  if (options_.goal_observable) {
    const float task_obs[3] = {static_cast<float>(goal[0]), static_cast<float>(goal[1]),
                               static_cast<float>(goal[2])};
    SetTaskObs(task_obs);
  } else {
    SetTaskObs({});
  }
}

void SawyerTask::DoReset(const ObsView& out) {
  mjModel* m = model_.get();
  mjData* d = data_.get();
  mj_resetData(m, d);
  sim::SetState(m, d, settled_);
  PlaceObjects(m, d);
  for (int i = 0; i < 3; ++i) d->mocap_pos[3 * goal_mocap_ + i] = goal_pos_[i];
  mj_forward(m, d);

  state_.obj_init = obj_pos_;
  RefreshState();
  state_.tcp_init = state_.tcp;
  InitTaskState(state_);
  WriteFrame(prev_frame_);
  WriteObs(out.env_obs);
}

Vec3 SawyerTask::DeriveGoal(const Vec3& obj, const Vec3& drawn_goal) const {
  Vec3 goal = drawn_goal;
  if (config_.goal_z_at_object) goal[2] = obj[2];
  return goal;
}

void SawyerTask::PlaceObjects(mjModel*, mjData* d) {
  if (obj_qpos_ < 0) return;
  const mjtNum upright[7] = {obj_pos_[0], obj_pos_[1], obj_pos_[2], 1, 0, 0, 0};
  mju_copy(d->qpos + obj_qpos_, upright, 7);
  mju_zero(d->qvel + obj_dof_, 6);
  mju_zero(d->qacc_warmstart + obj_dof_, 6);
}

void SawyerTask::SaveVariationXml(const std::string& path) const {
  if (!has_task()) {
    throw EpisodeStateError("env '" + id() + "': SaveVariationXml needs a task; call "
                            "SetTaskState or ResetTaskState first");
  }
  // Rebuild the reset state in copies (as DoReset does), move the start
  // poses into the body frames, and save the whole state as keyframe
  // "reset": the body frames alone leave hinges and slides at 0 and the arm
  // straight.
  sim::ModelPtr m(mj_copyModel(nullptr, model_.get()));
  sim::DataPtr d = sim::MakeData(m.get());
  mj_resetData(m.get(), d.get());
  sim::SetState(m.get(), d.get(), settled_);
  // PlaceObjects writes only into the model and data it is given.
  const_cast<SawyerTask*>(this)->PlaceObjects(m.get(), d.get());
  for (int i = 0; i < 3; ++i) d->mocap_pos[3 * goal_mocap_ + i] = goal_pos_[i];
  mj_forward(m.get(), d.get());
  if (obj_qpos_ >= 0) {
    mju_copy3(m->body_pos + 3 * obj_body_, d->qpos + obj_qpos_);
    mju_copy4(m->body_quat + 4 * obj_body_, d->qpos + obj_qpos_ + 3);
  }
  for (int b = 0; b < m->nbody; ++b) {
    if (m->body_mocapid[b] == goal_mocap_) mju_copy3(m->body_pos + 3 * b, goal_pos_.data());
    if (m->body_mocapid[b] == hand_mocap_) mju_copy3(m->body_pos + 3 * b, config_.hand_init.data());
  }
  SaveTaskModelXml(m.get(), config_.xml_file, path, sim::KeyframeXml(m.get(), d.get(), "reset"));
}

void SawyerTask::WriteObject2(const mjData*, float* pos_quat) const {
  std::fill(pos_quat, pos_quat + 7, 0.0f);
}

void SawyerTask::DoStep(std::span<const float> action, const StepView& out) {
  mjModel* m = model_.get();
  mjData* d = data_.get();
  mjtNum* mocap = d->mocap_pos + 3 * hand_mocap_;
  for (int i = 0; i < 3; ++i) {
    mocap[i] = std::clamp(mocap[i] + kActionScale * action[i], config_.hand_low[i],
                          config_.hand_high[i]);
  }
  d->ctrl[left_act_] = action[3];
  d->ctrl[right_act_] = action[3];

  WriteFrame(prev_frame_);  // the frame before this step becomes obs[18:36]
  const int raised = sim::StepAndCheck(m, d, kFrameSkip, /*throw_on_warning=*/false);
  if (raised > 0) {
    ++sim_warning_count_;
    last_sim_warning_ = config_.id + " step: " + sim::DescribeWarnings(d);
    sim::ClearWarnings(d);
    if (options_.throw_on_sim_warning) throw sim::SimulationWarningError(last_sim_warning_);
    // The state is not trustworthy: end the episode without reward.
    RefreshState();
    WriteObs(out.env_obs);
    *out.truncated = true;
    return;
  }
  RefreshState();
  WriteObs(out.env_obs);
  const RewardTerms terms = options_.reward_version == RewardVersion::kV1
                                ? ComputeRewardV1(state_, action)
                                : ComputeReward(state_, action);
  *out.reward = static_cast<float>(terms.reward);
  out.info[0] = terms.success ? 1.0f : 0.0f;
  out.info[1] = static_cast<float>(terms.near_object);
  out.info[2] = static_cast<float>(terms.grasp_success);
  out.info[3] = static_cast<float>(terms.grasp_reward);
  out.info[4] = static_cast<float>(terms.in_place_reward);
  out.info[5] = static_cast<float>(terms.obj_to_target);
  out.info[6] = static_cast<float>(terms.reward);
}

RewardTerms SawyerTask::EvaluateReward(const SawyerState& state,
                                       std::span<const float> action) const {
  if (action.size() != 4) {
    throw Error("env '" + config_.id + "': EvaluateReward needs 4 action values, got " +
                std::to_string(action.size()));
  }
  std::array<float, 4> clipped{};
  for (size_t i = 0; i < 4; ++i) {
    if (!std::isfinite(action[i])) {
      throw Error("env '" + config_.id + "': EvaluateReward: action[" + std::to_string(i) +
                  "] is not finite");
    }
    clipped[i] = std::clamp(action[i], -1.0f, 1.0f);
  }
  for (const Vec3* v : {&state.hand, &state.tcp, &state.left_pad, &state.right_pad, &state.obj,
                        &state.goal, &state.obj_init, &state.tcp_init, &state.hand_init,
                        &state.obj_head, &state.obj_head_init, &state.handle_init,
                        &state.obj2, &state.obj2_init, &state.left_finger, &state.obj2_head}) {
    for (double x : *v) {
      if (!std::isfinite(x)) throw Error("env '" + config_.id + "': EvaluateReward: a position is not finite");
    }
  }
  if (!std::isfinite(state.gripper_opening)) {
    throw Error("env '" + config_.id + "': EvaluateReward: gripper_opening is not finite");
  }
  if (!std::isfinite(state.joint_qpos) || !std::isfinite(state.obj_to_target_init) ||
      !std::isfinite(state.v1_max_dist) || !std::isfinite(state.v1_obj_height) ||
      !std::isfinite(state.v1_height_target) || !std::isfinite(state.v1_max_dist2)) {
    throw Error("env '" + config_.id + "': EvaluateReward: joint_qpos, obj_to_target_init or a v1_ field is not finite");
  }
  for (double x : state.obj_quat) {
    if (!std::isfinite(x)) throw Error("env '" + config_.id + "': EvaluateReward: obj_quat is not finite");
  }
  return options_.reward_version == RewardVersion::kV1 ? ComputeRewardV1(state, clipped)
                                                      : ComputeReward(state, clipped);
}

void SawyerTask::RefreshState() {
  const mjData* d = data_.get();
  state_.hand = ToVec3(d->site_xpos + 3 * hand_site_);
  state_.left_pad = ToVec3(d->site_xpos + 3 * left_pad_site_);
  state_.right_pad = ToVec3(d->site_xpos + 3 * right_pad_site_);
  state_.left_finger = state_.left_pad;
  for (int i = 0; i < 3; ++i) state_.tcp[i] = 0.5 * (state_.left_pad[i] + state_.right_pad[i]);
  state_.obj = ToVec3(d->xpos + 3 * obj_body_);
  state_.goal = goal_pos_;
  state_.gripper_opening = std::clamp(Distance(state_.left_pad, state_.right_pad) / 0.1, 0.0, 1.0);
  // MuJoCo stores (w, x, y, z); the observation uses the task's layout.
  const mjtNum* q = d->xquat + 4 * obj_quat_body_;
  static constexpr int kXyzwOrder[4] = {1, 2, 3, 0};
  for (int i = 0; i < 4; ++i) {
    switch (config_.obj_quat) {
      case QuatLayout::kXyzw: state_.obj_quat[i] = q[kXyzwOrder[i]]; break;
      case QuatLayout::kWxyz: state_.obj_quat[i] = q[i]; break;
      case QuatLayout::kZeros: state_.obj_quat[i] = 0.0; break;
    }
  }
  state_.touching_obj = false;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const int other = c.geom1 == obj_geom_ ? c.geom2 : (c.geom2 == obj_geom_ ? c.geom1 : -1);
    if (other == left_pad_geom_ || other == right_pad_geom_) {
      state_.touching_obj = true;
      break;
    }
  }
  RefreshTaskState(d, state_);
}

void SawyerTask::WriteFrame(float* frame) const {
  const mjData* d = data_.get();
  for (int i = 0; i < 3; ++i) {
    frame[kObsHand + i] =
        std::clamp(static_cast<float>(state_.hand[i]), kHandSpaceLow[i], kHandSpaceHigh[i]);
  }
  frame[kObsGripper] = static_cast<float>(state_.gripper_opening);
  for (int i = 0; i < 3; ++i) frame[kObsObj1Pos + i] = static_cast<float>(state_.obj[i]);
  for (int i = 0; i < 4; ++i) frame[kObsObj1Quat + i] = static_cast<float>(state_.obj_quat[i]);
  WriteObject2(d, frame + kObsObj2Pos);
}

void SawyerTask::WriteObs(std::span<float> obs) const {
  WriteFrame(obs.data());
  std::copy(prev_frame_, prev_frame_ + kObsFrame, obs.data() + kObsPrev);
  for (int i = 0; i < 3; ++i) {
    obs[kObsGoal + i] = options_.goal_observable ? static_cast<float>(goal_pos_[i]) : 0.0f;
  }
}

}  // namespace manyworlds::manipulation
