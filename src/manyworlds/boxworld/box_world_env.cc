#include "manyworlds/boxworld/box_world_env.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "manyworlds/boxworld/scripted_policy.h"
#include "manyworlds/boxworld/world_model.h"
#include "manyworlds/core/atomic_file.h"
#include "manyworlds/core/error.h"
#include "manyworlds/sim/mujoco_error.h"
#include "manyworlds/sim/warnings.h"

namespace manyworlds::boxworld {
namespace {

// Worlds drawn at construction to catch settings that cannot be satisfied.
constexpr uint64_t kProbeWorlds = 8;

int JointQpos(const mjModel* m, const std::string& name) {
  const int id = mj_name2id(m, mjOBJ_JOINT, name.c_str());
  if (id < 0) throw sim::MujocoError("box world model: no joint '" + name + "'");
  return m->jnt_qposadr[id];
}

}  // namespace

const char* BoxWorldEnv::IdOf(BoxTask task) {
  return task == BoxTask::kSimple ? "box-world-simple" : "box-world-complex";
}

EnvSpec BoxWorldEnv::MakeSpec(const Config& config) {
  const std::string id = IdOf(config.task);
  if (config.max_boxes < 1 || config.max_boxes > kMaxBoxesLimit) {
    throw ConfigError("env '" + id + "': option 'max_boxes' must be in [1, " +
                      std::to_string(kMaxBoxesLimit) + "], got " +
                      std::to_string(config.max_boxes));
  }
  try {
    config.distribution.Validate();
  } catch (const ConfigError& e) {
    throw ConfigError("env '" + id + "': " + e.what());
  }
  if (config.distribution.num_boxes[1] > config.max_boxes) {
    throw ConfigError("env '" + id + "': options 'num_boxes' and 'num_boxes_max' must be at " +
                      "most max_boxes = " + std::to_string(config.max_boxes) +
                      " (the observation's box slots), got up to " +
                      std::to_string(config.distribution.num_boxes[1]) +
                      " boxes; raise max_boxes (up to " + std::to_string(kMaxBoxesLimit) +
                      ") or lower num_boxes");
  }
  if (config.task == BoxTask::kComplex && config.distribution.num_boxes[0] < 1) {
    throw ConfigError("env '" + id + "': option 'num_boxes' must be in [1, " +
                      std::to_string(kMaxBoxesLimit) +
                      "] for the complex task (it pushes boxes), got " +
                      std::to_string(config.distribution.num_boxes[0]));
  }
  // settings that validate but cannot be satisfied (too crowded for the
  // target) fail here rather than at some later reset
  try {
    for (uint64_t seed = 0; seed < kProbeWorlds; ++seed) GenerateWorld(config.distribution, seed);
  } catch (const ConfigError& e) {
    throw ConfigError("env '" + id + "': " + e.what());
  }
  const float inf = std::numeric_limits<float>::infinity();
  EnvSpec spec;
  spec.id = id;
  spec.description = config.task == BoxTask::kSimple
                         ? "Box world (MuJoCo, generated worlds): reach the target"
                         : "Box world (MuJoCo, generated worlds): push every box to the target";
  spec.action_space = Space::Box(-1.0f, 1.0f, {3});
  if (config.targets_per_layout < 1) {
    throw ConfigError("env '" + id + "': option 'targets_per_layout' must be >= 1, got " +
                      std::to_string(config.targets_per_layout));
  }
  if (config.targets_per_layout > 1 && config.distribution.layout_seed >= 0) {
    throw ConfigError("env '" + id + "': option 'targets_per_layout' (" +
                      std::to_string(config.targets_per_layout) +
                      ") draws a layout per group and needs layout_seed = -1, got layout_seed = " +
                      std::to_string(config.distribution.layout_seed));
  }
  spec.env_obs_space = Space::Box(
      -inf, inf, {kAgentObs + kBoxObs * config.max_boxes + (config.target_in_obs ? 2 : 0)});
  spec.task_obs_space = Space::Box(-inf, inf, {2});
  spec.info_fields = {"success", "boxes_delivered", "distance", "sim_warnings"};
  spec.max_episode_steps = kEpisodeSteps;
  spec.uses_env_seed = false;
  return spec;
}

BoxWorldEnv::BoxWorldEnv(const Config& config) : Env(MakeSpec(config)), config_(config) {}

void BoxWorldEnv::SeedTask(uint64_t seed) {
  Env::SeedTask(seed);
  draws_ = 0;
  group_layout_ = -1;
}

TaskState BoxWorldEnv::DoSampleTaskState(Rng& task_rng) {
  try {
    if (config_.targets_per_layout <= 1) {
      return TaskState{id(), ToJson(config_.distribution.Sample(task_rng))};
    }
    // a new group: its layout seed comes from the task generator (62 bits,
    // so that it is a valid layout_seed); the group's targets follow it
    // (a crowded layout that leaves no room for a target is drawn again,
    // up to 20 times, as Sample does without groups)
    WorldDistribution grouped = config_.distribution;
    if (draws_++ % config_.targets_per_layout != 0) {
      grouped.layout_seed = group_layout_;
      return TaskState{id(), ToJson(grouped.Sample(task_rng))};
    }
    for (int attempt = 0;; ++attempt) {
      group_layout_ = static_cast<int64_t>(task_rng.NextU64() >> 2);
      grouped.layout_seed = group_layout_;
      try {
        return TaskState{id(), ToJson(grouped.Sample(task_rng))};
      } catch (const ConfigError&) {
        if (attempt + 1 == 20) throw;
      }
    }
  } catch (const ConfigError& e) {
    throw ConfigError("env '" + id() + "': " + e.what());
  }
}

TaskState BoxWorldEnv::DoGetTaskState() const { return TaskState{id(), ToJson(world_)}; }

void BoxWorldEnv::DoSetTaskState(const TaskState& state) {
  const TaskStateReader reader(state, id());  // checks the env name and the object
  WorldParams world;
  try {
    world = WorldFromJson(state.params);
  } catch (const ConfigError& e) {
    throw TaskStateError("task state for env '" + id() + "': " + e.what());
  }
  if (world.boxes.size() > static_cast<size_t>(config_.max_boxes)) {
    throw TaskStateError("task state for env '" + id() + "': the world has " +
                         std::to_string(world.boxes.size()) + " boxes, this env observes at most " +
                         "max_boxes = " + std::to_string(config_.max_boxes));
  }
  if (config_.task == BoxTask::kComplex && world.boxes.empty()) {
    throw TaskStateError("task state for env '" + id() +
                         "': the complex task needs at least one box, the world has none");
  }
  if (!model_ || !SameStructure(world_, world)) {
    sim::ModelPtr model = BuildWorldModel(world);
    sim::DataPtr data = sim::MakeData(model.get());
    model_ = std::move(model);
    data_ = std::move(data);
    ++models_built_;
    world_ = std::move(world);
    CacheIds();
  } else {
    world_ = std::move(world);
  }
  model_->site_pos[3 * target_site_ + 0] = world_.target[0];
  model_->site_pos[3 * target_site_ + 1] = world_.target[1];
  delivered_.assign(world_.boxes.size(), 0);
  const float target[2] = {config_.hide_target ? 0.0f : static_cast<float>(world_.target[0]),
                           config_.hide_target ? 0.0f : static_cast<float>(world_.target[1])};
  SetTaskObs(std::span<const float>(target, 2));
}

sim::Scene BoxWorldEnv::ActiveScene() const {
  return has_task() ? sim::Scene{model(), data()} : sim::Scene{};
}

void BoxWorldEnv::SaveSceneXml(const std::string& path) const {
  if (!has_task()) {
    throw EpisodeStateError("env '" + id() + "': SaveSceneXml needs a task; call SetTaskState "
                            "or ResetTaskState first");
  }
  AtomicWriteFile(path, WorldMjcf(world_).ToXml());
}

std::unique_ptr<Policy> BoxWorldEnv::CreateScriptedPolicy() const {
  return MakeScriptedPolicy(*this);
}

void BoxWorldEnv::CacheIds() {
  const mjModel* m = model_.get();
  agent_qpos_ = JointQpos(m, "agent_x");
  agent_qvel_ = m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, "agent_x")];
  box_qpos_.clear();
  for (size_t i = 0; i < world_.boxes.size(); ++i) {
    box_qpos_.push_back(JointQpos(m, "box" + std::to_string(i)));
  }
  target_site_ = mj_name2id(m, mjOBJ_SITE, "target");
  if (target_site_ < 0) throw sim::MujocoError("box world model: no site 'target'");
  ctrl_scale_.assign(static_cast<size_t>(m->nu), 0.0);
  for (int i = 0; i < m->nu; ++i) ctrl_scale_[i] = m->actuator_ctrlrange[2 * i + 1];
}

double BoxWorldEnv::PlanarDistance(int qpos_address) const {
  const double* q = data_->qpos + qpos_address;
  return std::hypot(q[0] - world_.target[0], q[1] - world_.target[1]);
}

void BoxWorldEnv::WriteObs(std::span<float> out) const {
  std::fill(out.begin(), out.end(), 0.0f);
  const double* qpos = data_->qpos;
  const double* qvel = data_->qvel;
  const double yaw = qpos[agent_qpos_ + 2];
  out[0] = static_cast<float>(world_.floor_size);
  out[1] = static_cast<float>(qpos[agent_qpos_]);
  out[2] = static_cast<float>(qpos[agent_qpos_ + 1]);
  out[3] = static_cast<float>(std::cos(yaw));
  out[4] = static_cast<float>(std::sin(yaw));
  out[5] = static_cast<float>(qvel[agent_qvel_]);
  out[6] = static_cast<float>(qvel[agent_qvel_ + 1]);
  out[7] = static_cast<float>(qvel[agent_qvel_ + 2]);
  for (size_t k = 0; k < box_qpos_.size(); ++k) {
    float* slot = out.data() + kAgentObs + kBoxObs * k;
    slot[0] = 1.0f;
    for (int j = 0; j < 7; ++j) slot[1 + j] = static_cast<float>(qpos[box_qpos_[k] + j]);
    slot[8] = static_cast<float>(delivered_[k]);
  }
  if (config_.target_in_obs && !config_.hide_target) {
    float* target = out.data() + kAgentObs + kBoxObs * config_.max_boxes;
    target[0] = static_cast<float>(world_.target[0]);
    target[1] = static_cast<float>(world_.target[1]);
  }
}

void BoxWorldEnv::DoReset(const ObsView& out) {
  mjModel* m = model_.get();
  mjData* d = data_.get();
  mj_resetData(m, d);
  d->qpos[agent_qpos_] = world_.agent_start[0];
  d->qpos[agent_qpos_ + 1] = world_.agent_start[1];
  d->qpos[agent_qpos_ + 2] = world_.agent_start_yaw;
  for (size_t k = 0; k < box_qpos_.size(); ++k) {
    const BoxParams& b = world_.boxes[k];
    double* q = d->qpos + box_qpos_[k];
    q[0] = b.start[0];
    q[1] = b.start[1];
    q[2] = b.size;
    q[3] = std::cos(b.start_yaw / 2);
    q[4] = 0;
    q[5] = 0;
    q[6] = std::sin(b.start_yaw / 2);
  }
  mj_forward(m, d);
  std::fill(delivered_.begin(), delivered_.end(), 0);
  reached_ = false;
  WriteObs(out.env_obs);
}

int BoxWorldEnv::BoxesOutsideTheArena() const {
  // Outside the walls or below the floor: hit hard enough, a small box can
  // pass through a wall or the floor within one physics step.
  const double limit = world_.floor_size / 2 + kWallThickness;
  int outside = 0;
  std::string where;
  for (size_t k = 0; k < box_qpos_.size(); ++k) {
    const double* q = data_->qpos + box_qpos_[k];
    if (std::abs(q[0]) > limit || std::abs(q[1]) > limit || q[2] < -world_.boxes[k].size) {
      ++outside;
      if (where.empty()) {
        where = "box " + std::to_string(k) + " at (" + std::to_string(q[0]) + ", " +
                std::to_string(q[1]) + ", " + std::to_string(q[2]) + ")";
      }
    }
  }
  if (outside > 0 && config_.throw_on_sim_warning) {
    throw sim::SimulationWarningError(id() + ": " + std::to_string(outside) +
                                      " box(es) left the arena (" + where +
                                      "; the walls end at +-" + std::to_string(limit) + " m)");
  }
  return outside;
}

void BoxWorldEnv::DoStep(std::span<const float> action, const StepView& out) {
  mjModel* m = model_.get();
  mjData* d = data_.get();
  for (int i = 0; i < m->nu; ++i) d->ctrl[i] = action[i] * ctrl_scale_[i];
  int warnings = sim::StepAndCheck(m, d, kFrameSkip, config_.throw_on_sim_warning, id());
  if (warnings == 0) warnings = BoxesOutsideTheArena();
  out.info[3] = static_cast<float>(warnings);
  if (warnings > 0) {  // the state is not to be trusted: end without reward
    WriteObs(out.env_obs);
    *out.reward = 0.0f;
    *out.truncated = true;
    return;
  }
  double reward = 0.0;
  double distance = 0.0;
  int delivered = 0;
  bool success = false;
  if (config_.task == BoxTask::kSimple) {
    const double dist = PlanarDistance(agent_qpos_);
    if (dist < world_.success_radius) {
      reached_ = true;
      reward = kSuccessBonus;
    } else {
      distance = dist;
      reward = -kDistanceCost * dist;
    }
    success = reached_;
  } else {
    for (size_t k = 0; k < box_qpos_.size(); ++k) {
      if (!delivered_[k]) {
        const double dist = PlanarDistance(box_qpos_[k]);
        if (dist < world_.success_radius) {
          delivered_[k] = 1;
          reward += kSuccessBonus;
        } else {
          distance += dist;
        }
      }
      delivered += delivered_[k];
    }
    reward -= kDistanceCost * distance;
    success = delivered == static_cast<int>(box_qpos_.size());
  }
  WriteObs(out.env_obs);
  *out.reward = static_cast<float>(reward);
  *out.terminated = success;
  out.info[0] = success ? 1.0f : 0.0f;
  out.info[1] = static_cast<float>(delivered);
  out.info[2] = static_cast<float>(distance);
}

}  // namespace manyworlds::boxworld
