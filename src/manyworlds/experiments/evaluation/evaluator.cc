#include "manyworlds/experiments/evaluator.h"

#include <algorithm>
#include <chrono>

#include <torch/torch.h>

#include "manyworlds/agents/actor.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/experiments/collector.h"
#include "manyworlds/experiments/episode_tracker.h"

namespace manyworlds::experiments {
namespace {

constexpr int64_t kMaxEvalEnvs = 64;

nlohmann::json OptionalJson(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

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
                     uint64_t seed, int num_threads)
    : tasks_(tasks), episodes_(episodes_per_task), seed_(seed) {
  if (episodes_per_task < 1) {
    throw ConfigError("evaluation episodes must be >= 1, got " +
                      std::to_string(episodes_per_task));
  }
  facts_ = InspectEnvs(tasks, registry);
  // waves of equal size: cap envs per task, then spread episodes evenly
  const int64_t cap = std::max<int64_t>(1, kMaxEvalEnvs / tasks.size());
  const int64_t waves = (episodes_ + cap - 1) / cap;
  slots_ = (episodes_ + waves - 1) / waves;
  std::vector<std::unique_ptr<Env>> envs;
  for (int64_t t = 0; t < tasks.size(); ++t) {
    for (int64_t j = 0; j < slots_; ++j) envs.push_back(tasks.MakeEnv(t, registry));
  }
  exec_ = std::make_unique<BatchedExecutor>(
      std::move(envs), ExecutorOptions{.num_threads = num_threads, .auto_reset = true});
}

Evaluator::~Evaluator() = default;

EvalResult Evaluator::Run(const PolicyFn& policy) { return RunEpisodes(policy, [] {}); }

EvalResult Evaluator::RunEpisodes(const PolicyFn& policy,
                                  const std::function<void()>& new_episodes,
                                  const ObserveFn& observe) {
  const auto start = std::chrono::steady_clock::now();
  const int64_t num_tasks = tasks_.size();
  const int64_t n = num_tasks * slots_;
  const int64_t obs_dim = facts_.obs_dim;
  const int64_t info_size = static_cast<int64_t>(exec_->info_fields().size());
  std::vector<double> returns(num_tasks, 0.0), lengths(num_tasks, 0.0), successes(num_tasks, 0.0);
  std::vector<float> actions(n * facts_.action_dim);
  torch::Tensor task_index = torch::empty({n}, torch::kInt64);
  for (int64_t i = 0; i < n; ++i) task_index[i] = i / slots_;

  std::vector<std::vector<EpisodeResult>> episodes(num_tasks,
                                                   std::vector<EpisodeResult>(episodes_));
  std::vector<double> ep_return(n), ep_length(n);
  std::vector<float> step_rewards(n), step_ended(n);
  std::vector<char> ep_success(n), active(n);
  for (int64_t first = 0; first < episodes_; first += slots_) {
    if (first > 0) new_episodes();
    for (int64_t i = 0; i < n; ++i) {
      const int64_t t = i / slots_;
      const int64_t e = first + i % slots_;
      Env& env = exec_->env(static_cast<int>(i));
      env.Seed(MixSeed(MixSeed(seed_, t), e));
      env.SeedTask(MixSeed(MixSeed(seed_ + 1, t), e));
      const auto& variations = tasks_.tasks[t].variations;
      exec_->SetTaskState(static_cast<int>(i), variations[e % variations.size()]);
      ep_return[i] = 0.0;
      ep_length[i] = 0.0;
      ep_success[i] = 0;
      active[i] = e < episodes_;
    }
    int64_t remaining = std::count(active.begin(), active.end(), 1);
    while (remaining > 0) {
      const torch::Tensor obs =
          torch::from_blob(const_cast<float*>(exec_->env_obs().data()), {n, obs_dim},
                           torch::kFloat32);
      const torch::Tensor unit = policy(obs, task_index).contiguous();
      const torch::Tensor obs_before = observe ? obs.clone() : torch::Tensor();
      PolicyToEnvActions(unit.data_ptr<float>(), n, facts_, actions.data());
      exec_->Step(actions);
      const auto rewards = exec_->rewards();
      const auto terminated = exec_->terminated();
      const auto truncated = exec_->truncated();
      const auto info = exec_->info();
      if (observe) {
        for (int64_t i = 0; i < n; ++i) {
          step_rewards[i] = rewards[i];
          step_ended[i] = terminated[i] || truncated[i] ? 1.0f : 0.0f;
        }
        observe(obs_before, unit, step_rewards.data(), step_ended.data());
      }
      for (int64_t i = 0; i < n; ++i) {
        if (!active[i]) continue;
        ep_return[i] += rewards[i];
        ep_length[i] += 1;
        if (facts_.success_index >= 0 && info[i * info_size + facts_.success_index] > kSuccessThreshold) {
          ep_success[i] = 1;
        }
        if (terminated[i] || truncated[i]) {
          const int64_t t = i / slots_;
          returns[t] += ep_return[i];
          lengths[t] += ep_length[i];
          successes[t] += ep_success[i];
          EpisodeResult& record = episodes[t][first + i % slots_];
          record.episode_return = ep_return[i];
          record.length = static_cast<int64_t>(ep_length[i]);
          if (facts_.success_index >= 0) record.success = ep_success[i] != 0;
          active[i] = 0;
          --remaining;
        }
      }
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
