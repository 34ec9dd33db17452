#include "manyworlds/core/wrappers/multi_env.h"

#include <algorithm>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

std::string JoinFields(const std::vector<std::string>& fields) {
  std::string joined;
  for (const auto& f : fields) joined += (joined.empty() ? "" : ", ") + f;
  return "[" + joined + "]";
}

EnvSpec MakeSpec(const std::vector<std::unique_ptr<Env>>& envs, std::string id) {
  if (envs.empty()) throw ConfigError("MultiEnv needs at least one env, got none");
  for (size_t i = 0; i < envs.size(); ++i) {
    if (!envs[i]) throw ConfigError("MultiEnv: env " + std::to_string(i) + " is null");
  }
  const EnvSpec& first = envs[0]->spec();
  auto mismatch = [&](size_t i, const std::string& what, const std::string& got,
                      const std::string& expected) {
    throw ConfigError("MultiEnv: env " + std::to_string(i) + " ('" + envs[i]->id() + "') has " +
                      what + " " + got + ", but env 0 ('" + first.id + "') has " + expected +
                      "; all envs must share action space, env observation space shape and "
                      "info fields");
  };
  EnvSpec spec;
  std::string ids;
  int64_t limit = 0;
  bool unlimited = false;
  bool uses_env_seed = false;
  for (size_t i = 0; i < envs.size(); ++i) {
    const EnvSpec& s = envs[i]->spec();
    if (!(s.action_space == first.action_space)) {
      mismatch(i, "action space", s.action_space.ToString(), first.action_space.ToString());
    }
    const bool same_kind = s.env_obs_space.kind() == first.env_obs_space.kind() &&
                           s.env_obs_space.shape() == first.env_obs_space.shape();
    const bool same_discrete = !first.env_obs_space.is_discrete() ||
                               s.env_obs_space.n() == first.env_obs_space.n();
    if (!same_kind || !same_discrete) {
      mismatch(i, "env observation space", s.env_obs_space.ToString(),
               first.env_obs_space.ToString());
    }
    if (s.info_fields != first.info_fields) {
      mismatch(i, "info fields", JoinFields(s.info_fields), JoinFields(first.info_fields));
    }
    ids += (i == 0 ? "" : ",") + s.id;
    unlimited = unlimited || s.max_episode_steps == 0;
    uses_env_seed = uses_env_seed || s.uses_env_seed;
    limit = std::max(limit, s.max_episode_steps);
  }
  spec.id = id.empty() ? "multi-env(" + ids + ")" : std::move(id);
  spec.description =
      "one of " + std::to_string(envs.size()) + " envs, selected by the task: " + ids;
  spec.action_space = first.action_space;
  spec.env_obs_space = first.env_obs_space;
  if (first.env_obs_space.is_box()) {
    // Members may bound their observations differently (each Sawyer task has
    // its own goal range): the union of the boxes holds every member's.
    std::vector<float> low = first.env_obs_space.low();
    std::vector<float> high = first.env_obs_space.high();
    for (const auto& env : envs) {
      const Space& box = env->spec().env_obs_space;
      for (size_t j = 0; j < low.size(); ++j) {
        low[j] = std::min(low[j], box.low()[j]);
        high[j] = std::max(high[j], box.high()[j]);
      }
    }
    spec.env_obs_space = Space::Box(std::move(low), std::move(high), first.env_obs_space.shape());
  }
  spec.task_obs_space = Space::Discrete(static_cast<int64_t>(envs.size()));
  spec.info_fields = first.info_fields;
  spec.max_episode_steps = unlimited ? 0 : limit;
  spec.uses_env_seed = uses_env_seed;
  return spec;
}

}  // namespace

MultiEnv::MultiEnv(std::vector<std::unique_ptr<Env>> envs, std::string env_id)
    : Env(MakeSpec(envs, std::move(env_id))), envs_(std::move(envs)) {
  member_task_obs_.reserve(envs_.size());
  for (const auto& env : envs_) {
    member_task_obs_.emplace_back(env->spec().task_obs_space.flat_size(), 0.0f);
  }
}

void MultiEnv::Seed(uint64_t seed) {
  Env::Seed(seed);
  for (size_t i = 0; i < envs_.size(); ++i) envs_[i]->Seed(MixSeed(seed, i));
}

void MultiEnv::SeedTask(uint64_t seed) {
  Env::SeedTask(seed);
  for (size_t i = 0; i < envs_.size(); ++i) envs_[i]->SeedTask(MixSeed(seed, i));
}

void MultiEnv::SetMaxEpisodeSteps(int64_t max_episode_steps) {
  for (auto& env : envs_) env->SetMaxEpisodeSteps(max_episode_steps);
  Env::SetMaxEpisodeSteps(max_episode_steps);
}

TaskState MultiEnv::DoSampleTaskState(Rng& task_rng) {
  const int index = static_cast<int>(task_rng.UniformInt(envs_.size()));
  return MakeIndexedTaskState(id(), index, envs_[index]->SampleTaskState());
}

TaskState MultiEnv::DoGetTaskState() const {
  return MakeIndexedTaskState(id(), active_, envs_[active_]->GetTaskState());
}

void MultiEnv::DoSetTaskState(const TaskState& state) {
  const auto [index, member_state] = ReadIndexedTaskState(state, id(), num_envs());
  try {
    envs_[index]->SetTaskState(member_state);
  } catch (const TaskStateError& e) {
    throw IndexedTaskRejected(
        id(), "env " + std::to_string(index) + " ('" + envs_[index]->id() + "')", e);
  }
  active_ = index;
  const float task_obs[1] = {static_cast<float>(index)};
  SetTaskObs(task_obs);
}

void MultiEnv::DoReset(const ObsView& out) {
  envs_[active_]->Reset(ObsView{out.env_obs, member_task_obs_[active_], out.pixels});
}

void MultiEnv::DoStep(std::span<const float> action, const StepView& out) {
  envs_[active_]->Step(action, StepView{out.env_obs, member_task_obs_[active_], out.reward,
                                        out.terminated, out.truncated, out.info, out.pixels});
}

}  // namespace manyworlds
