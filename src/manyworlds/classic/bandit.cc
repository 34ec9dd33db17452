#include "manyworlds/classic/bandit.h"

#include <algorithm>

#include "manyworlds/classic/common.h"

namespace manyworlds::classic {

EnvSpec BanditEnv::MakeSpec(const Config& config) {
  CheckIntOption(kId, "n_arms", config.n_arms, 2, 10000);
  CheckIntOption(kId, "horizon", config.horizon, 1);
  EnvSpec spec;
  spec.id = kId;
  spec.description = "Bernoulli multi-armed bandit; the task is the arm probabilities";
  spec.action_space = Space::Discrete(config.n_arms);
  spec.env_obs_space = Space::Box(0.0f, 1.0f, {config.n_arms + 1});
  spec.task_obs_space = Space::Box(0.0f, 1.0f, {config.n_arms});
  spec.info_fields = {"regret", "best_arm"};
  spec.max_episode_steps = config.horizon;
  return spec;
}

BanditEnv::BanditEnv(const Config& config)
    : Env(MakeSpec(config)),
      n_arms_(config.n_arms),
      hide_task_(config.hide_task),
      probs_(config.n_arms, 0.0) {}

TaskState BanditEnv::DoSampleTaskState(Rng& task_rng) {
  std::vector<double> probs(n_arms_);
  for (double& p : probs) p = task_rng.Uniform();
  return TaskState{kId, {{"probs", probs}}};
}

TaskState BanditEnv::DoGetTaskState() const { return TaskState{kId, {{"probs", probs_}}}; }

void BanditEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, kId);
  reader.ExpectKeys({"probs"});
  probs_ = reader.Numbers("probs", n_arms_, 0.0, 1.0);
  best_prob_ = *std::max_element(probs_.begin(), probs_.end());
  std::vector<float> obs(n_arms_, 0.0f);
  if (!hide_task_) std::copy(probs_.begin(), probs_.end(), obs.begin());
  SetTaskObs(obs);
}

void BanditEnv::DoReset(const ObsView& out) {
  std::fill(out.env_obs.begin(), out.env_obs.end(), 0.0f);
}

void BanditEnv::DoStep(std::span<const float> action, const StepView& out) {
  const auto arm = static_cast<size_t>(action[0]);
  const bool success = env_rng().Bernoulli(probs_[arm]);
  std::fill(out.env_obs.begin(), out.env_obs.end(), 0.0f);
  out.env_obs[arm] = 1.0f;
  out.env_obs[n_arms_] = success ? 1.0f : 0.0f;
  *out.reward = success ? 1.0f : 0.0f;
  out.info[0] = static_cast<float>(best_prob_ - probs_[arm]);
  out.info[1] = probs_[arm] == best_prob_ ? 1.0f : 0.0f;
}

}  // namespace manyworlds::classic
