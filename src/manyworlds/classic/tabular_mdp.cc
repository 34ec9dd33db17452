#include "manyworlds/classic/tabular_mdp.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "manyworlds/classic/common.h"
#include "manyworlds/core/error.h"

namespace manyworlds::classic {
namespace {

// Rows of P may deviate from 1 by rounding only.
constexpr double kRowSumTolerance = 1e-6;

}  // namespace

EnvSpec TabularMdpEnv::MakeSpec(const Config& config) {
  const int64_t s = CheckIntOption(kId, "n_states", config.n_states, 1, 100);
  const int64_t a = CheckIntOption(kId, "n_actions", config.n_actions, 1, 100);
  CheckIntOption(kId, "horizon", config.horizon, 1);
  EnvSpec spec;
  spec.id = kId;
  spec.description = "Random tabular MDP; the task is the reward table and transition tensor";
  spec.action_space = Space::Discrete(a);
  spec.env_obs_space = Space::Box(0.0f, 1.0f, {s + 1});
  spec.task_obs_space = Space::Box(0.0f, 1.0f, {s * a + s * a * s});
  spec.info_fields = {"expected_reward"};
  spec.max_episode_steps = config.horizon;
  return spec;
}

TabularMdpEnv::TabularMdpEnv(const Config& config)
    : Env(MakeSpec(config)),
      n_states_(config.n_states),
      n_actions_(config.n_actions),
      hide_task_(config.hide_task),
      rewards_(n_states_ * n_actions_, 0.0),
      transitions_(n_states_ * n_actions_ * n_states_, 0.0) {}

TaskState TabularMdpEnv::MakeState(const std::vector<double>& rewards,
                                   const std::vector<double>& transitions) const {
  return TaskState{kId,
                   {{"n_states", n_states_},
                    {"n_actions", n_actions_},
                    {"rewards", rewards},
                    {"transitions", transitions}}};
}

TaskState TabularMdpEnv::DoSampleTaskState(Rng& task_rng) {
  std::vector<double> rewards(n_states_ * n_actions_);
  for (double& r : rewards) r = task_rng.Uniform();
  std::vector<double> transitions(n_states_ * n_actions_ * n_states_);
  for (int64_t row = 0; row < n_states_ * n_actions_; ++row) {
    double* p = transitions.data() + row * n_states_;
    for (int64_t k = 0; k < n_states_; ++k) p[k] = task_rng.Normal();
    // Subtract the max before exp for a stable softmax.
    const double max_logit = *std::max_element(p, p + n_states_);
    double total = 0.0;
    for (int64_t k = 0; k < n_states_; ++k) total += p[k] = std::exp(p[k] - max_logit);
    for (int64_t k = 0; k < n_states_; ++k) p[k] /= total;
  }
  return MakeState(rewards, transitions);
}

TaskState TabularMdpEnv::DoGetTaskState() const { return MakeState(rewards_, transitions_); }

void TabularMdpEnv::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, kId);
  reader.ExpectKeys({"n_states", "n_actions", "rewards", "transitions"});
  // The sizes must match this instance's options.
  reader.Integer("n_states", n_states_, n_states_);
  reader.Integer("n_actions", n_actions_, n_actions_);
  auto rewards = reader.Numbers("rewards", rewards_.size(), 0.0, 1.0);
  auto transitions = reader.Numbers("transitions", transitions_.size(), 0.0, 1.0);
  for (int64_t row = 0; row < n_states_ * n_actions_; ++row) {
    double total = 0.0;
    for (int64_t k = 0; k < n_states_; ++k) total += transitions[row * n_states_ + k];
    if (std::abs(total - 1.0) > kRowSumTolerance) {
      throw TaskStateError(
          "task state for env '" + std::string(kId) + "': field 'transitions' row for (state " +
          std::to_string(row / n_actions_) + ", action " + std::to_string(row % n_actions_) +
          ") sums to " + std::to_string(total) + "; each row must sum to 1");
    }
  }
  rewards_ = std::move(rewards);
  transitions_ = std::move(transitions);
  std::vector<float> obs(spec().task_obs_space.flat_size(), 0.0f);
  if (!hide_task_) {
    std::copy(rewards_.begin(), rewards_.end(), obs.begin());
    std::copy(transitions_.begin(), transitions_.end(), obs.begin() + rewards_.size());
  }
  SetTaskObs(obs);
}

void TabularMdpEnv::DoReset(const ObsView& out) {
  state_ = 0;
  std::fill(out.env_obs.begin(), out.env_obs.end(), 0.0f);
  out.env_obs[state_] = 1.0f;
}

void TabularMdpEnv::DoStep(std::span<const float> action, const StepView& out) {
  const auto a = static_cast<int64_t>(action[0]);
  const double mean = reward_mean(state_, a);
  const bool success = env_rng().Bernoulli(mean);
  // Inverse-CDF draw of the next state.
  const double* p = transitions_.data() + (state_ * n_actions_ + a) * n_states_;
  const double u = env_rng().Uniform();
  double cumulative = 0.0;
  int64_t next = -1;
  for (int64_t k = 0; k < n_states_; ++k) {
    cumulative += p[k];
    if (u < cumulative) {
      next = k;
      break;
    }
  }
  // A row summing to slightly less than 1 leaves u unmatched: take the last
  // reachable state.
  if (next < 0) {
    next = n_states_ - 1;
    while (next > 0 && p[next] == 0.0) --next;
  }
  state_ = next;
  std::fill(out.env_obs.begin(), out.env_obs.end(), 0.0f);
  out.env_obs[state_] = 1.0f;
  out.env_obs[n_states_] = success ? 1.0f : 0.0f;
  *out.reward = success ? 1.0f : 0.0f;
  out.info[0] = static_cast<float>(mean);
}

}  // namespace manyworlds::classic
