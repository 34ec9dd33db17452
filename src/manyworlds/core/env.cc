#include "manyworlds/core/env.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/core/error.h"

namespace manyworlds {

int EnvSpec::InfoIndex(std::string_view name) const {
  for (size_t i = 0; i < info_fields.size(); ++i) {
    if (info_fields[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::optional<float> Info::Find(std::string_view name) const {
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return values[i];
  }
  return std::nullopt;
}

float Info::Get(std::string_view name) const {
  if (auto v = Find(name)) return *v;
  std::string fields;
  for (const auto& n : names) fields += (fields.empty() ? "" : ", ") + n;
  throw Error("info has no field '" + std::string(name) + "' (fields: " +
              (fields.empty() ? "none" : fields) + ")");
}

Env::Env(EnvSpec spec) : spec_(std::move(spec)) {
  task_obs_.assign(spec_.task_obs_space.flat_size(), 0.0f);
  clipped_action_.assign(spec_.action_space.flat_size(), 0.0f);
}

void Env::Seed(uint64_t seed) { env_rng_.Seed(seed); }

void Env::SeedTask(uint64_t seed) { task_rng_.Seed(seed); }

TaskState Env::SampleTaskState() { return DoSampleTaskState(task_rng_); }

TaskState Env::GetTaskState() const {
  if (!has_task_) {
    throw EpisodeStateError("env '" + spec_.id +
                            "': no task set yet; call SetTaskState, ResetTaskState or Reset first");
  }
  return DoGetTaskState();
}

void Env::SetTaskState(const TaskState& state) {
  DoSetTaskState(state);
  has_task_ = true;
  phase_ = Phase::kNeedsReset;
}

void Env::SetTaskObs(std::span<const float> task_obs) {
  const size_t expected = static_cast<size_t>(spec_.task_obs_space.flat_size());
  if (task_obs.size() != expected) {
    throw Error("env '" + spec_.id + "': task observation has " + std::to_string(task_obs.size()) +
                " values, its space " + spec_.task_obs_space.ToString() + " has " +
                std::to_string(expected));
  }
  // A wrapper may have changed the task observation space after Env's
  // constructor sized the buffer; this resizes at most once.
  task_obs_.resize(expected);
  std::copy(task_obs.begin(), task_obs.end(), task_obs_.begin());
}

void Env::SetMaxEpisodeSteps(int64_t max_episode_steps) {
  if (max_episode_steps < 0) {
    throw ConfigError("env '" + spec_.id + "': max_episode_steps must be >= 0 (0: no limit), got " +
                      std::to_string(max_episode_steps));
  }
  spec_.max_episode_steps = max_episode_steps;
  if (phase_ == Phase::kRunning) phase_ = Phase::kNeedsReset;
}

Observation Env::Reset() {
  Observation obs;
  obs.env_obs.resize(spec_.env_obs_space.flat_size());
  obs.task_obs.resize(spec_.task_obs_space.flat_size());
  obs.pixels.resize(spec_.pixel_space.flat_size());
  Reset(ObsView{obs.env_obs, obs.task_obs, obs.pixels});
  return obs;
}

StepResult Env::Step(std::span<const float> action) {
  StepResult result;
  result.obs.env_obs.resize(spec_.env_obs_space.flat_size());
  result.obs.task_obs.resize(spec_.task_obs_space.flat_size());
  result.info.names = spec_.info_fields;
  result.info.values.resize(spec_.info_fields.size());
  result.obs.pixels.resize(spec_.pixel_space.flat_size());
  Step(action, StepView{result.obs.env_obs, result.obs.task_obs, &result.reward,
                        &result.terminated, &result.truncated, result.info.values,
                        result.obs.pixels});
  return result;
}

void Env::CheckView(size_t env_obs, size_t task_obs, size_t info, size_t pixels) const {
  if (env_obs != static_cast<size_t>(spec_.env_obs_space.flat_size()) ||
      task_obs != static_cast<size_t>(spec_.task_obs_space.flat_size()) ||
      info != spec_.info_fields.size() ||
      pixels != static_cast<size_t>(spec_.pixel_space.flat_size())) {
    throw Error("env '" + spec_.id + "': output buffers have sizes (env_obs " +
                std::to_string(env_obs) + ", task_obs " + std::to_string(task_obs) + ", info " +
                std::to_string(info) + ", pixels " + std::to_string(pixels) + "), expected (" +
                std::to_string(spec_.env_obs_space.flat_size()) + ", " +
                std::to_string(spec_.task_obs_space.flat_size()) + ", " +
                std::to_string(spec_.info_fields.size()) + ", " +
                std::to_string(spec_.pixel_space.flat_size()) + ")");
  }
}

void Env::Reset(const ObsView& out) {
  CheckView(out.env_obs.size(), out.task_obs.size(), spec_.info_fields.size(), out.pixels.size());
  if (!has_task_) ResetTaskState();
  DoReset(out);
  std::copy(task_obs_.begin(), task_obs_.end(), out.task_obs.begin());
  elapsed_steps_ = 0;
  phase_ = Phase::kRunning;
}

void Env::ValidateAction(std::span<const float> action) {
  const Space& space = spec_.action_space;
  if (static_cast<int64_t>(action.size()) != space.flat_size()) {
    throw InvalidActionError("env '" + spec_.id + "': action has " + std::to_string(action.size()) +
                             " values, expected " + std::to_string(space.flat_size()) +
                             " for action space " + space.ToString());
  }
  for (size_t i = 0; i < action.size(); ++i) {
    if (!std::isfinite(action[i])) {
      throw InvalidActionError("env '" + spec_.id + "': action element " + std::to_string(i) +
                               " is " + std::to_string(action[i]) +
                               "; actions must be finite (action space " + space.ToString() + ")");
    }
  }
  // Covers a wrapper that changed the action space after Env's constructor
  // sized the buffer (no allocation once sized).
  clipped_action_.resize(action.size());
  if (space.is_discrete()) {
    if (!space.Contains(action)) {
      throw InvalidActionError("env '" + spec_.id + "': action " + std::to_string(action[0]) +
                               " is not in " + space.ToString() + " (allowed: integers 0.." +
                               std::to_string(space.n() - 1) + ")");
    }
    clipped_action_[0] = action[0];
  } else {
    // Box actions outside the bounds are clipped, as Meta-World does.
    std::copy(action.begin(), action.end(), clipped_action_.begin());
    space.Clip(clipped_action_);
  }
}

void Env::Step(std::span<const float> action, const StepView& out) {
  if (phase_ == Phase::kNeedsReset) {
    throw EpisodeStateError("env '" + spec_.id +
                            "': Step called before Reset (after construction or SetTaskState)");
  }
  if (phase_ == Phase::kEnded) {
    throw EpisodeStateError("env '" + spec_.id +
                            "': Step called after the episode ended (terminated or truncated); "
                            "call Reset to start a new episode");
  }
  CheckView(out.env_obs.size(), out.task_obs.size(), out.info.size(), out.pixels.size());
  ValidateAction(action);
  *out.reward = 0.0f;
  *out.terminated = false;
  *out.truncated = false;
  std::fill(out.info.begin(), out.info.end(), 0.0f);
  DoStep(clipped_action_, out);
  std::copy(task_obs_.begin(), task_obs_.end(), out.task_obs.begin());
  ++elapsed_steps_;
  // As Gymnasium's TimeLimit: truncated may be set together with terminated.
  if (spec_.max_episode_steps > 0 && elapsed_steps_ >= spec_.max_episode_steps) {
    *out.truncated = true;
  }
  if (*out.terminated || *out.truncated) phase_ = Phase::kEnded;
}

}  // namespace manyworlds
