#include "manyworlds/experiments/loops/collector.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"

namespace manyworlds::experiments {
namespace {

// The round stream of experiment.seed (unchanged since the first trainer, so
// runs keep their numbers).
constexpr uint64_t kRoundStream = 0x726f756e64;  // "round"
constexpr uint64_t kTrialStream = 0x747269616c;  // "trial"

}  // namespace

void PolicyToEnvActions(const float* policy, int64_t rows, const EnvFacts& facts, float* out) {
  if (facts.num_actions > 0) {
    std::copy(policy, policy + rows, out);
    return;
  }
  const int64_t a = facts.action_dim;
  for (int64_t r = 0; r < rows; ++r) {
    for (int64_t j = 0; j < a; ++j) {
      const float lo = facts.action_low[j];
      const float hi = facts.action_high[j];
      const float u = std::clamp(policy[r * a + j], -1.0f, 1.0f);
      out[r * a + j] = lo + 0.5f * (u + 1.0f) * (hi - lo);
    }
  }
}

namespace {

std::vector<std::unique_ptr<Env>> MakeEnvs(const TaskSet& tasks, const Registry& registry,
                                           int64_t envs_per_task) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int64_t i = 0; i < tasks.size() * envs_per_task; ++i) {
    envs.push_back(tasks.MakeEnv(i / envs_per_task, registry));
  }
  return envs;
}

}  // namespace

Collector::Collector(const TaskSet& tasks, const Registry& registry, int64_t envs_per_task,
                     int num_threads)
    : Collector(tasks, MakeEnvs(tasks, registry, envs_per_task), nullptr, envs_per_task,
                num_threads) {}

Collector::Collector(const TaskSet& tasks, const Registry& registry, const EnvFacts& facts,
                     int64_t envs_per_task, int num_threads)
    : Collector(tasks, MakeEnvs(tasks, registry, envs_per_task), &facts, envs_per_task,
                num_threads) {}

Collector::Collector(const TaskSet& tasks, std::vector<std::unique_ptr<Env>> envs,
                     const EnvFacts* facts, int64_t envs_per_task, int num_threads)
    : tasks_(tasks),
      facts_(facts != nullptr ? *facts
                              : FactsOf(tasks, [&](int64_t t) -> const Env& {
                                  return *envs[t * envs_per_task];
                                })),
      envs_per_task_(envs_per_task),
      num_envs_(tasks.size() * envs_per_task),
      tracker_(tasks.size() * envs_per_task, static_cast<int64_t>(facts_.info_size),
               facts_.success_index) {
  for (int64_t i = 0; i < num_envs_; ++i) env_tasks_.push_back(i / envs_per_task);
  exec_ = std::make_unique<BatchedExecutor>(
      std::move(envs), ExecutorOptions{.num_threads = num_threads, .auto_reset = true});
  env_actions_.assign(num_envs_ * facts_.action_dim, 0.0f);
  env_variations_.assign(num_envs_, 0);
}

void Collector::BeginRound(uint64_t seed, int64_t round, int64_t rounds_per_trial,
                           int64_t support_rounds) {
  if (rounds_per_trial < 1) throw Error("Collector: rounds_per_trial must be >= 1");
  const uint64_t base = MixSeed(MixSeed(seed, kRoundStream), round);
  const uint64_t trial =
      MixSeed(MixSeed(seed, kTrialStream), static_cast<uint64_t>(round / rounds_per_trial));
  const bool split = tasks_.has_split() && rounds_per_trial > 1;
  const bool support = round % rounds_per_trial < support_rounds;
  BeginEpisodes([&](int64_t i) {
    Rng r(MixSeed(base, i));
    EnvStart start;
    start.seed = r.NextU64();
    start.task_seed = r.NextU64();
    const uint64_t variations = tasks_.tasks[env_tasks_[i]].variations.size();
    if (split) {
      Rng trial_rng(MixSeed(trial, i));
      const auto group = static_cast<int64_t>(
          trial_rng.UniformInt(static_cast<uint64_t>(tasks_.Groups(env_tasks_[i]))));
      start.variation =
          support ? tasks_.SupportVariation(
                        group, static_cast<int64_t>(r.UniformInt(tasks_.support_variations)))
                  : tasks_.QueryVariation(
                        group, static_cast<int64_t>(r.UniformInt(tasks_.query_variations)));
    } else if (variations > 1) {
      Rng trial_rng(MixSeed(trial, i));
      start.variation = static_cast<int64_t>(
          rounds_per_trial == 1 ? r.UniformInt(variations) : trial_rng.UniformInt(variations));
    }
    return start;
  });
}

void Collector::BeginEpisodes(const std::function<EnvStart(int64_t env)>& start) {
  for (int64_t i = 0; i < num_envs_; ++i) {
    const EnvStart s = start(i);
    Env& env = exec_->env(static_cast<int>(i));
    env.Seed(s.seed);
    env.SeedTask(s.task_seed);
    const auto& variations = tasks_.tasks[env_tasks_[i]].variations;
    const int64_t v = s.variation % static_cast<int64_t>(variations.size());
    exec_->SetTaskState(static_cast<int>(i), variations[v]);
    env_variations_[i] = v;
    tracker_.Restart(i);
  }
}

void Collector::StartEpisode(int64_t env, int64_t variation) {
  const auto& variations = tasks_.tasks[env_tasks_[env]].variations;
  const int64_t v = variation % static_cast<int64_t>(variations.size());
  exec_->SetTaskState(static_cast<int>(env), variations[v]);
  env_variations_[env] = v;
  tracker_.Restart(env);
}

torch::Tensor Collector::PolicyObservations() const {
  if (facts_.pixel_shape.empty()) {
    return torch::from_blob(const_cast<float*>(exec_->env_obs().data()),
                            {num_envs_, facts_.obs_dim}, torch::kFloat32);
  }
  std::vector<int64_t> shape = {num_envs_};
  shape.insert(shape.end(), facts_.pixel_shape.begin(), facts_.pixel_shape.end());
  return torch::from_blob(const_cast<uint8_t*>(exec_->pixels().data()), shape, torch::kUInt8);
}

void Collector::ResetEpisodes() {
  exec_->Reset();
  for (int64_t i = 0; i < num_envs_; ++i) tracker_.Restart(i);
}

void Collector::TerminateOnSuccess(bool on) {
  if (on && facts_.success_index < 0) {
    throw ConfigError("terminate_on_success: these envs report no success");
  }
  tracker_.EndAtSuccess(on);
}

void Collector::RestartSucceeded() {
  for (const int64_t i : succeeded_) exec_->ResetEnv(static_cast<int>(i));
  succeeded_.clear();
}

void Collector::StepEnvs(std::span<const float> policy_actions) {
  try {
    if (env_units_) {
      exec_->Step(policy_actions);
      return;
    }
    PolicyToEnvActions(policy_actions.data(), num_envs_, facts_, env_actions_.data());
    exec_->Step(env_actions_);
  } catch (const InvalidActionError&) {
    // a policy whose networks diverged (a step size far too large, a log-std bound of -1e308)
    // acts with NaN: said so here, where every loop and protocol steps its envs, instead of as
    // the env's "action element 0 is nan" (looked for only once an env refused an action, so
    // the step itself pays nothing)
    for (size_t k = 0; k < policy_actions.size(); ++k) {
      if (!std::isfinite(policy_actions[k])) {
        throw Error("the policy's action " + std::to_string(k % facts_.action_dim) + " of env " +
                    std::to_string(k / facts_.action_dim) + " is " +
                    std::to_string(policy_actions[k]) +
                    ": its networks diverged; lower the agent's learning rates or step sizes, or "
                    "bring its bounds (log_std_min, ...) to their usual range");
      }
    }
    throw;
  }
}

void Collector::Step(std::span<const float> policy_actions, EpisodeTotals& totals) {
  StepEnvs(policy_actions);
  CountEpisodes([&](const EpisodeRecord& r) { totals.Add(r); });
}

}  // namespace manyworlds::experiments
