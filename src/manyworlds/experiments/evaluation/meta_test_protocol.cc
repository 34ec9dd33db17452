#include "manyworlds/experiments/evaluation/meta_test_protocol.h"

#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <sstream>

#include "manyworlds/agents/actor.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/experiments/loops/collector.h"
#include "manyworlds/experiments/loops/episode_tracker.h"

namespace manyworlds::experiments {
namespace {

constexpr int64_t kMaxEnvs = 64;

// Rows where `frozen` is true keep their values from `before` (a waiting
// env's actor state does not move). Per-env tensors have the env first.
torch::Tensor KeepRows(const torch::Tensor& before, const torch::Tensor& after,
                       const torch::Tensor& frozen) {
  if (!before.defined() || !after.defined() || before.sizes() != after.sizes()) return after;
  std::vector<int64_t> shape(after.dim(), 1);
  shape[0] = after.size(0);
  return torch::where(frozen.reshape(shape), before, after);
}

// The per-env tensors of an actor state a step may change (a waiting env's
// recorded steps are marked invalid instead; see StepOutcome::valid).
using PerEnvState = std::map<std::string, torch::Tensor>;

void Freeze(agents::ActorState& state, const PerEnvState& before, const torch::Tensor& frozen) {
  c10::InferenceMode inference;
  for (auto& [name, tensor] : state.tensors) {
    const auto it = before.find(name);
    if (it != before.end()) tensor = KeepRows(it->second, tensor, frozen);
  }
}

// Sums over the episodes of one phase of one task.
struct PhaseTotals {
  double returns = 0.0, successes = 0.0;
  int64_t episodes = 0;
};

}  // namespace

void MetaTestConfig::Validate() const {
  auto in_range = [](const char* field, int64_t value, int64_t low, int64_t high,
                     const char* note = "") {
    if (value >= low && value <= high) return;
    std::ostringstream msg;
    msg << "'meta_test." << field << "' must be in [" << low << ", " << high << "]" << note
        << ", got " << value;
    throw ConfigError(msg.str());
  };
  if (protocol != kMetalearningEvaluation && protocol != kPerVariation) {
    throw ConfigError("'meta_test.protocol' must be one of " + std::string(kMetalearningEvaluation) +
                      " (Meta-World v3's), " + kPerVariation + "; got '" + protocol + "'");
  }
  if (task_select != "random" && task_select != "pseudorandom") {
    throw ConfigError("'meta_test.task_select' must be one of random, pseudorandom; got '" +
                      task_select + "'");
  }
  in_range("num_evals", num_evals, 1, 100000);
  in_range("adaptation_steps", adaptation_steps, 1, 1000);
  in_range("adaptation_episodes", adaptation_episodes, 1, 10000);
  in_range("meta_batch_size", meta_batch_size, 1, 4096);
  in_range("total_tasks_per_cls", total_tasks_per_cls, 0, 1000000, " (0: every variation)");
  in_range("exploration_episodes", exploration_episodes, 0, 10000);
  in_range("evaluation_episodes", evaluation_episodes, 1, 10000);
  in_range("trials_per_task", trials_per_task, 1, 100000);
}

int64_t GoalsOf(const TaskSpec& task, const MetaTestConfig& config) {
  const int64_t all = static_cast<int64_t>(task.variations.size());
  return config.total_tasks_per_cls > 0 ? std::min(all, config.total_tasks_per_cls) : all;
}

std::string DescribeProtocol(const MetaTestConfig& c) {
  std::ostringstream out;
  if (c.per_variation()) {
    out << kPerVariation << ": " << c.trials_per_task << " trials per task of "
        << c.exploration_episodes << " exploration + " << c.evaluation_episodes
        << " evaluation episodes";
  } else {
    out << kMetalearningEvaluation << " (Meta-World v3's): " << c.num_evals << " rounds x "
        << c.meta_batch_size << " envs, " << c.adaptation_steps << " x "
        << c.adaptation_episodes << " adaptation episodes per env, then "
        << c.evaluation_episodes << " evaluation episodes per task"
        << (c.terminate_on_success ? " ending at success" : "");
  }
  return out.str();
}

MetaTestConfig MetaTestConfigOf(const nlohmann::json& result) {
  MetaTestConfig c;
  c.protocol = kPerVariation;
  c.VisitFields([&](const char* key, auto& value) {
    if (result.is_object() && result.contains(key)) {
      value = result[key].get<std::remove_reference_t<decltype(value)>>();
    }
  });
  return c;
}

nlohmann::json MetaTestResult::ToJson() const {
  const bool has_pre_adaptation = !config.per_variation() || config.exploration_episodes > 0;
  nlohmann::json tasks = nlohmann::json::object();
  for (const auto& t : per_task) {
    tasks[t.task] = {{"success", OptionalJson(t.success)},
                     {"return", t.mean_return},
                     {"pre_adaptation_success", OptionalJson(t.pre_success)},
                     {"pre_adaptation_return", has_pre_adaptation
                                                   ? nlohmann::json(t.pre_mean_return)
                                                   : nlohmann::json(nullptr)},
                     {"trial_return", t.trial_return}};
  }
  nlohmann::json out = {
      {"step", step},
      {"success_rate", OptionalJson(success_rate)},
      {"return", mean_return},
      {"pre_adaptation_success_rate", OptionalJson(pre_adaptation_success_rate)},
      {"pre_adaptation_return", has_pre_adaptation ? nlohmann::json(pre_adaptation_return)
                                                   : nlohmann::json(nullptr)},
      {"trial_return", trial_return},
      {"episodes_per_task", AsEvalResult().episodes_per_task},
      {"per_task", tasks},
      {"wall_s", wall_s}};
  // the protocol and its own parameters
  MetaTestConfig c = config;
  c.VisitFields([&](const char* key, const auto& value) {
    const std::string_view owner = MetaTestConfig::ProtocolOf(key);
    if (owner.empty() || owner == c.protocol) out[key] = value;
  });
  return out;
}

void MetaTestResult::AverageTasks(bool has_success, bool has_pre_adaptation) {
  const double n = static_cast<double>(per_task.size());
  double success_sum = 0.0, pre_success_sum = 0.0;
  for (const MetaTestTaskResult& r : per_task) {
    mean_return += r.mean_return / n;
    pre_adaptation_return += r.pre_mean_return / n;
    trial_return += r.trial_return / n;
    success_sum += r.success.value_or(0.0);
    pre_success_sum += r.pre_success.value_or(0.0);
  }
  if (has_success) {
    success_rate = success_sum / n;
    if (has_pre_adaptation) pre_adaptation_success_rate = pre_success_sum / n;
  }
}

EvalResult MetaTestResult::AsEvalResult() const {
  EvalResult r;
  r.step = step;
  r.episodes_per_task = config.per_variation()
                            ? config.trials_per_task * config.evaluation_episodes
                            : config.num_evals * config.evaluation_episodes;
  for (const auto& t : per_task) {
    TaskEvalResult task;
    task.task = t.task;
    task.success = t.success;
    task.mean_return = t.mean_return;
    r.per_task.push_back(std::move(task));
  }
  r.mean_success = success_rate;
  r.mean_return = mean_return;
  r.wall_s = wall_s;
  return r;
}

MetaTestProtocol::MetaTestProtocol(const TaskSet& test_tasks, const Registry& registry,
                                   const MetaTestConfig& config, uint64_t seed, int num_threads,
                                   const EnvFacts* facts)
    : tasks_(test_tasks), config_(config), seed_(seed) {
  config.Validate();
  const int64_t num_tasks = test_tasks.size();
  if (test_tasks.has_split() && !config.per_variation()) {
    throw ConfigError(
        "meta_test: the held-out tasks have a support/query split, which only the "
        "per_variation protocol follows (set meta_test.protocol: per_variation)");
  }
  if (config.per_variation()) {
    const int64_t cap = std::max<int64_t>(1, kMaxEnvs / num_tasks);
    const int64_t waves = (config.trials_per_task + cap - 1) / cap;
    slots_ = (config.trials_per_task + waves - 1) / waves;
  } else {
    // v3 deals each task's goals to its envs in turn (make_ml_envs also
    // asserts that they split evenly; here an env may have one goal more)
    if (config.meta_batch_size % num_tasks != 0) {
      throw ConfigError("'meta_test.meta_batch_size' (" + std::to_string(config.meta_batch_size) +
                        ") must be a multiple of the number of held-out tasks (" +
                        std::to_string(num_tasks) + ")");
    }
    slots_ = config.meta_batch_size / num_tasks;
    for (const TaskSpec& task : test_tasks.tasks) {
      const int64_t goals = GoalsOf(task, config);
      if (goals < slots_) {
        throw ConfigError("meta_test: task " + task.name + " has " + std::to_string(goals) +
                          " goals (variations, at most total_tasks_per_cls), fewer than its " +
                          std::to_string(slots_) + " envs (meta_batch_size / tasks): lower "
                          "meta_test.meta_batch_size or give the task more variations");
      }
    }
  }
  collector_ = facts != nullptr
                   ? std::make_unique<Collector>(test_tasks, registry, *facts, slots_, num_threads)
                   : std::make_unique<Collector>(test_tasks, registry, slots_, num_threads);
  facts_ = collector_->facts();
}

MetaTestProtocol::~MetaTestProtocol() = default;

MetaTestResult MetaTestProtocol::RunMetaTest(agents::Actor& actor) {
  collector_->ActionsInEnvUnits(actor.ActsInEnvUnits());
  return config_.per_variation() ? RunPerVariation(actor) : RunMetalearningEvaluation(actor);
}

MetaTestResult MetaTestProtocol::RunPerVariation(agents::Actor& actor) {
  const auto start = std::chrono::steady_clock::now();
  const int64_t num_tasks = tasks_.size();
  const int64_t n = num_tasks * slots_;
  const int64_t obs_dim = facts_.obs_dim;
  const bool has_success = facts_.success_index >= 0;
  const bool observe = actor.WantsOutcomes();
  torch::Tensor task_index = torch::empty({n}, torch::kInt64);
  for (int64_t i = 0; i < n; ++i) task_index[i] = i / slots_;
  // [phase][task]; phase 0 = exploration, 1 = evaluation
  std::vector<std::vector<PhaseTotals>> totals(2, std::vector<PhaseTotals>(num_tasks));
  BatchedExecutor& exec = collector_->executor();
  std::vector<MetaTestEpisode> episodes;
  std::vector<int64_t> episodes_done(n);
  torch::Tensor waiting = torch::zeros({n}, torch::kBool);
  bool* waiting_flags = waiting.data_ptr<bool>();
  agents::StepOutcome outcome;
  outcome.reward = torch::zeros({n});
  outcome.ended = torch::zeros({n});
  float* reward_out = outcome.reward.data_ptr<float>();
  float* ended_out = outcome.ended.data_ptr<float>();

  for (int64_t first = 0; first < config_.trials_per_task; first += slots_) {
    agents::ActorState state = actor.Initial(n);
    state.held_out_tasks = held_out_;
    // sampled actions from the protocol's own stream
    state.generator = at::make_generator<at::CPUGeneratorImpl>(MixSeed(seed_, first));
    std::vector<char> in_trial(n);
    for (int64_t i = 0; i < n; ++i) in_trial[i] = first + i % slots_ < config_.trials_per_task;
    const torch::Tensor trial_envs = torch::from_blob(in_trial.data(), {n}, torch::kBool).clone();
    for (int phase = 0; phase < 2; ++phase) {
      const int64_t count = phase == 0 ? config_.exploration_episodes : config_.evaluation_episodes;
      if (count == 0) continue;
      const agents::ActMode mode = phase == 0 || config_.sample_evaluation
                                       ? agents::ActMode::kSample
                                       : agents::ActMode::kDeterministic;
      // the variation of episode k of this phase in env i's trial
      auto variation = [&](int64_t i, int64_t k) {
        const int64_t v = first + i % slots_;
        if (!tasks_.has_split()) return v;
        const int64_t group = v % tasks_.Groups(i / slots_);
        return phase == 0 ? tasks_.SupportVariation(group, k) : tasks_.QueryVariation(group, k);
      };
      collector_->BeginEpisodes([&](int64_t i) {
        const int64_t v = first + i % slots_;
        const uint64_t trial_seed = MixSeed(MixSeed(seed_, i / slots_), v);
        return Collector::EnvStart{MixSeed(trial_seed, phase), MixSeed(trial_seed + 1, phase),
                                   variation(i, 0)};
      });
      for (int64_t i = 0; i < n; ++i) {
        episodes_done[i] = 0;
        waiting_flags[i] = !in_trial[i];
      }
      int64_t remaining = std::count(in_trial.begin(), in_trial.end(), 1);
      std::vector<int64_t> next_episode;  // envs that go on to their phase's next variation
      while (remaining > 0) {
        const torch::Tensor obs = torch::from_blob(
            const_cast<float*>(collector_->observations().data()), {n, obs_dim}, torch::kFloat32);
        const PerEnvState before = state.tensors;
        const torch::Tensor valid = waiting.logical_not().to(torch::kFloat32);
        // frames for pixel policies; observers (stateful actors) read the state obs
        const torch::Tensor action =
            actor.Act(collector_->PolicyObservations(), task_index, state, mode)
                .action.contiguous();
        // obs views the executor's buffer, which the step overwrites
        const torch::Tensor acted_on = observe ? obs.clone() : torch::Tensor();
        collector_->StepEnvs({action.data_ptr<float>(), static_cast<size_t>(action.numel())});
        if (observe) {
          const auto rewards = exec.rewards();
          const auto terminated = exec.terminated();
          const auto truncated = exec.truncated();
          for (int64_t i = 0; i < n; ++i) {
            reward_out[i] = rewards[i];
            ended_out[i] = terminated[i] || truncated[i] ? 1.0f : 0.0f;
          }
          outcome.action = action;
          outcome.obs = acted_on;
          outcome.valid = valid;
          actor.Observe(outcome, state);
        }
        Freeze(state, before, waiting);
        collector_->CountEpisodes([&](const EpisodeRecord& r) {
          if (waiting_flags[r.env]) return;  // past its episodes of this phase
          episodes.push_back({tasks_.tasks[r.env / slots_].name, first + r.env % slots_,
                              phase == 1, episodes_done[r.env], r.episode_return, r.length,
                              has_success ? std::optional<bool>(r.success) : std::nullopt});
          PhaseTotals& p = totals[phase][r.env / slots_];
          p.returns += r.episode_return;
          p.successes += r.success ? 1.0 : 0.0;
          ++p.episodes;
          if (++episodes_done[r.env] == count) {
            waiting_flags[r.env] = true;
            --remaining;
          } else if (tasks_.has_split()) {
            next_episode.push_back(r.env);
          }
        });
        for (const int64_t i : next_episode) {
          collector_->StartEpisode(i, variation(i, episodes_done[i]));
        }
        next_episode.clear();
      }
      if (phase == 0) actor.Adapt(trial_envs, state);
    }
  }

  MetaTestResult result;
  result.config = config_;
  for (int64_t t = 0; t < num_tasks; ++t) {
    const PhaseTotals& pre = totals[0][t];
    const PhaseTotals& post = totals[1][t];
    MetaTestTaskResult r;
    r.task = tasks_.tasks[t].name;
    r.mean_return = post.returns / post.episodes;
    if (has_success) r.success = post.successes / post.episodes;
    if (pre.episodes > 0) {
      r.pre_mean_return = pre.returns / pre.episodes;
      if (has_success) r.pre_success = pre.successes / pre.episodes;
    }
    r.trial_return = (pre.returns + post.returns) / config_.trials_per_task;
    result.per_task.push_back(std::move(r));
  }
  result.AverageTasks(has_success, config_.exploration_episodes > 0);
  result.episodes = std::move(episodes);
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace manyworlds::experiments
