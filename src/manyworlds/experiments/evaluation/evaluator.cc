#include "manyworlds/experiments/evaluation/evaluator.h"

#include <torch/torch.h>

#include <algorithm>
#include <chrono>

#include "manyworlds/agents/actor.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/experiments/loops/collector.h"

namespace manyworlds::experiments {
namespace {

constexpr int64_t kMaxEvalEnvs = 64;

}  // namespace

nlohmann::json EvalResult::ToJson() const {
  nlohmann::json tasks = nlohmann::json::object();
  for (const auto& t : per_task) {
    tasks[t.task] = {{"success", OptionalJson(t.success)},
                     {"return", t.mean_return},
                     {"length", t.mean_length}};
  }
  return {{"step", step},
          {"episodes_per_task", episodes_per_task},
          {"mean_success", OptionalJson(mean_success)},
          {"mean_return", mean_return},
          {"per_task", tasks},
          {"wall_s", wall_s}};
}

Evaluator::Evaluator(const TaskSet& tasks, const Registry& registry, int64_t episodes_per_task,
                     uint64_t seed, int num_threads, const EnvFacts* facts)
    : tasks_(tasks), episodes_(episodes_per_task), seed_(seed) {
  if (episodes_per_task < 1) {
    throw ConfigError("evaluation episodes must be >= 1, got " +
                      std::to_string(episodes_per_task));
  }
  // waves of equal size: cap envs per task, then spread episodes evenly
  const int64_t cap = std::max<int64_t>(1, kMaxEvalEnvs / tasks.size());
  const int64_t waves = (episodes_ + cap - 1) / cap;
  slots_ = (episodes_ + waves - 1) / waves;
  collector_ = facts != nullptr
                   ? std::make_unique<Collector>(tasks, registry, *facts, slots_, num_threads)
                   : std::make_unique<Collector>(tasks, registry, slots_, num_threads);
  facts_ = collector_->facts();
}

Evaluator::~Evaluator() = default;

void Evaluator::TerminateOnSuccess(bool on) {
  collector_->TerminateOnSuccess(on && facts_.success_index >= 0);
}

EvalResult Evaluator::Run(const PolicyFn& policy) {
  collector_->ActionsInEnvUnits(false);
  return RunEpisodes(policy, [] {});
}

EvalResult Evaluator::RunEpisodes(const PolicyFn& policy,
                                  const std::function<void()>& new_episodes,
                                  const ObserveFn& observe) {
  const auto start = std::chrono::steady_clock::now();
  const int64_t num_tasks = tasks_.size();
  const int64_t n = num_tasks * slots_;
  const int64_t obs_dim = facts_.obs_dim;
  std::vector<double> returns(num_tasks, 0.0), lengths(num_tasks, 0.0), successes(num_tasks, 0.0);
  torch::Tensor task_index = torch::empty({n}, torch::kInt64);
  for (int64_t i = 0; i < n; ++i) task_index[i] = i / slots_;

  std::vector<std::vector<EpisodeResult>> episodes(num_tasks,
                                                   std::vector<EpisodeResult>(episodes_));
  std::vector<float> step_rewards(n), step_ended(n);
  std::vector<char> active(n);
  BatchedExecutor& exec = collector_->executor();
  for (int64_t first = 0; first < episodes_; first += slots_) {
    if (first > 0) new_episodes();
    collector_->BeginEpisodes([&](int64_t i) {
      const int64_t t = i / slots_;
      const int64_t e = first + i % slots_;
      return Collector::EnvStart{MixSeed(MixSeed(seed_, t), e), MixSeed(MixSeed(seed_ + 1, t), e),
                                 e};
    });
    for (int64_t i = 0; i < n; ++i) active[i] = first + i % slots_ < episodes_;
    int64_t remaining = std::count(active.begin(), active.end(), 1);
    while (remaining > 0) {
      const torch::Tensor obs = torch::from_blob(
          const_cast<float*>(collector_->observations().data()), {n, obs_dim}, torch::kFloat32);
      // frames for pixel policies; observers (stateful actors) read the state obs
      const torch::Tensor unit = policy(collector_->PolicyObservations(), task_index).contiguous();
      const torch::Tensor obs_before = observe ? obs.clone() : torch::Tensor();
      collector_->StepEnvs({unit.data_ptr<float>(), static_cast<size_t>(unit.numel())});
      if (observe) {
        const auto rewards = exec.rewards();
        const auto terminated = exec.terminated();
        const auto truncated = exec.truncated();
        for (int64_t i = 0; i < n; ++i) {
          step_rewards[i] = rewards[i];
          step_ended[i] = terminated[i] || truncated[i] ? 1.0f : 0.0f;
        }
        observe(obs_before, unit, step_rewards.data(), step_ended.data());
      }
      // slots past the last episode of the last wave step along, unrecorded
      collector_->CountEpisodes([&](const EpisodeRecord& ep) {
        const int64_t i = ep.env;
        if (!active[i]) return;
        const int64_t t = i / slots_;
        returns[t] += ep.episode_return;
        lengths[t] += static_cast<double>(ep.length);
        successes[t] += ep.success ? 1.0 : 0.0;
        EpisodeResult& record = episodes[t][first + i % slots_];
        record.episode_return = ep.episode_return;
        record.length = ep.length;
        if (facts_.success_index >= 0) record.success = ep.success;
        active[i] = 0;
        --remaining;
      });
    }
  }

  EvalResult result;
  result.episodes_per_task = episodes_;
  double sum_success = 0.0, sum_return = 0.0;
  for (int64_t t = 0; t < num_tasks; ++t) {
    TaskEvalResult r;
    r.task = tasks_.tasks[t].name;
    r.mean_return = returns[t] / static_cast<double>(episodes_);
    r.mean_length = lengths[t] / static_cast<double>(episodes_);
    if (facts_.success_index >= 0) r.success = successes[t] / static_cast<double>(episodes_);
    r.episodes = std::move(episodes[t]);
    sum_success += r.success.value_or(0.0);
    sum_return += r.mean_return;
    result.per_task.push_back(std::move(r));
  }
  if (facts_.success_index >= 0) result.mean_success = sum_success / num_tasks;
  result.mean_return = sum_return / num_tasks;
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

EvalResult Evaluator::Run(agents::Actor& actor) {
  collector_->ActionsInEnvUnits(actor.ActsInEnvUnits());
  const int64_t n = tasks_.size() * slots_;
  agents::ActorState state = actor.Initial(n);
  const torch::Tensor all_envs = torch::ones({n}, torch::kBool);
  ObserveFn observe;
  if (actor.WantsOutcomes()) {
    observe = [&](const torch::Tensor& obs, const torch::Tensor& actions, const float* rewards,
                  const float* ended) {
      agents::StepOutcome outcome;
      outcome.obs = obs;
      outcome.action = actions;
      outcome.reward = torch::from_blob(const_cast<float*>(rewards), {n}, torch::kFloat32);
      outcome.ended = torch::from_blob(const_cast<float*>(ended), {n}, torch::kFloat32);
      actor.Observe(outcome, state);
    };
  }
  // every batch of episodes runs on new variations: a new task for the actor
  return RunEpisodes(
      [&](const torch::Tensor& obs, const torch::Tensor& task) {
        return actor.Act(obs, task, state, agents::ActMode::kDeterministic).action;
      },
      [&] { actor.Reset(all_envs, agents::ResetScope::kTask, state); }, observe);
}

}  // namespace manyworlds::experiments
