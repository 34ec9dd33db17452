// Meta-World v3's metalearning_evaluation (meta_test_protocol.h says what
// it does, step by step); MetaTestProtocol::RunPerVariation is the other
// protocol.
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <numeric>

#include "manyworlds/agents/actor.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/experiments/evaluation/meta_test_protocol.h"
#include "manyworlds/experiments/loops/collector.h"
#include "manyworlds/experiments/loops/episode_tracker.h"

namespace manyworlds::experiments {
namespace {

constexpr uint64_t kGoalStream = 0x676f616c;  // "goal"

// One env's goals (variation indices) and how it picks one each round, as
// v3's RandomTaskSelectWrapper / PseudoRandomTaskSelectWrapper do.
class GoalPicker {
 public:
  GoalPicker(std::vector<int64_t> goals, bool pseudorandom, uint64_t seed)
      : goals_(std::move(goals)), pseudorandom_(pseudorandom), rng_(seed) {}
  int64_t Next() {
    if (!pseudorandom_) return goals_[rng_.UniformInt(goals_.size())];
    next_ = (next_ + 1) % static_cast<int64_t>(goals_.size());
    if (next_ == 0) {
      for (size_t k = goals_.size() - 1; k > 0; --k) {
        std::swap(goals_[k], goals_[rng_.UniformInt(k + 1)]);
      }
    }
    return goals_[next_];
  }

 private:
  std::vector<int64_t> goals_;
  bool pseudorandom_;
  Rng rng_;
  int64_t next_ = -1;
};

// Sums over episodes.
struct Totals {
  double returns = 0.0, successes = 0.0;
  int64_t episodes = 0;
  void Add(const EpisodeRecord& r) {
    returns += r.episode_return;
    successes += r.success ? 1.0 : 0.0;
    ++episodes;
  }
};

}  // namespace

MetaTestResult MetaTestProtocol::RunMetalearningEvaluation(agents::Actor& actor) {
  const auto start = std::chrono::steady_clock::now();
  const int64_t num_tasks = tasks_.size();
  const int64_t per_task = slots_;
  const int64_t n = num_tasks * per_task;
  const int64_t obs_dim = facts_.obs_dim;
  const bool has_success = facts_.success_index >= 0;
  const bool observe = actor.WantsOutcomes();
  BatchedExecutor& exec = collector_->executor();
  torch::Tensor task_index = torch::empty({n}, torch::kInt64);
  for (int64_t i = 0; i < n; ++i) task_index[i] = i / per_task;
  const torch::Tensor all_envs = torch::ones({n}, torch::kBool);

  std::vector<GoalPicker> pickers;
  for (int64_t i = 0; i < n; ++i) {
    const int64_t goals = GoalsOf(tasks_.tasks[i / per_task], config_);
    std::vector<int64_t> mine;
    for (int64_t v = i % per_task; v < goals; v += per_task) mine.push_back(v);
    pickers.emplace_back(std::move(mine), config_.task_select == "pseudorandom",
                         MixSeed(MixSeed(seed_, kGoalStream), i));
  }

  // the outcome of a step for actors that watch (RL2's context, MAML's and PEARL's records)
  agents::StepOutcome outcome;
  outcome.reward = torch::zeros({n});
  outcome.ended = torch::zeros({n});
  float* reward_out = outcome.reward.data_ptr<float>();
  float* ended_out = outcome.ended.data_ptr<float>();
  torch::Tensor ended_envs = torch::zeros({n}, torch::kBool);
  bool* ended_flags = ended_envs.data_ptr<bool>();
  // Steps every env once with the actor's actions; on_end(record) for each
  // episode that ended, in env order; the actor sees the step and is told
  // where episodes ended.
  auto step = [&](agents::ActorState& state, agents::ActMode mode, auto&& on_end) {
    const torch::Tensor obs = torch::from_blob(
        const_cast<float*>(collector_->observations().data()), {n, obs_dim}, torch::kFloat32);
    // frames for pixel policies; observers (stateful actors) read the state obs
    const torch::Tensor action =
        actor.Act(collector_->PolicyObservations(), task_index, state, mode).action.contiguous();
    // obs views the executor's buffer, which the step overwrites
    const torch::Tensor acted_on = observe ? obs.clone() : torch::Tensor();
    collector_->StepEnvs({action.data_ptr<float>(), static_cast<size_t>(action.numel())});
    if (observe) {
      // before CountEpisodes, which resets the envs that ended at success
      const auto rewards = exec.rewards();
      std::copy(rewards.begin(), rewards.end(), reward_out);
    }
    std::fill(ended_flags, ended_flags + n, false);
    bool any_ended = false;
    collector_->CountEpisodes([&](const EpisodeRecord& r) {
      ended_flags[r.env] = true;
      any_ended = true;
      on_end(r);
    });
    if (observe) {
      for (int64_t i = 0; i < n; ++i) ended_out[i] = ended_flags[i] ? 1.0f : 0.0f;
      outcome.action = action;
      outcome.obs = acted_on;
      actor.Observe(outcome, state);
    }
    if (any_ended) actor.Reset(ended_envs, agents::ResetScope::kEpisode, state);
  };

  std::vector<Totals> pre(num_tasks);
  std::vector<double> success_sum(num_tasks, 0.0), return_sum(num_tasks, 0.0);
  std::vector<MetaTestEpisode> episodes;
  for (int64_t round = 0; round < config_.num_evals; ++round) {
    // 1. new goals (v3's sample_tasks), a fresh actor (agent.init())
    collector_->BeginEpisodes([&](int64_t i) {
      const uint64_t env_seed = MixSeed(MixSeed(seed_, static_cast<uint64_t>(round)), i);
      return Collector::EnvStart{env_seed, MixSeed(env_seed, 1), pickers[i].Next()};
    });
    agents::ActorState state = actor.Initial(n);
    state.held_out_tasks = held_out_;
    state.generator = at::make_generator<at::CPUGeneratorImpl>(MixSeed(seed_, round));
    // 2. adaptation
    collector_->TerminateOnSuccess(false);
    for (int64_t a = 0; a < config_.adaptation_steps; ++a) {
      collector_->ResetEpisodes();
      std::vector<int64_t> done(n, 0);
      int64_t short_of = n;  // envs with fewer than adaptation_episodes episodes
      while (short_of > 0) {
        step(state, agents::ActMode::kSample, [&](const EpisodeRecord& r) {
          if (done[r.env] >= config_.adaptation_episodes) return;
          if (a == 0) pre[r.env / per_task].Add(r);
          episodes.push_back({tasks_.tasks[r.env / per_task].name, round, false, done[r.env],
                              r.episode_return, r.length,
                              has_success ? std::optional<bool>(r.success) : std::nullopt});
          if (++done[r.env] == config_.adaptation_episodes) --short_of;
        });
      }
      actor.Adapt(all_envs, state);
    }
    // 3. evaluation: the first evaluation_episodes episodes of each task to end
    collector_->TerminateOnSuccess(config_.terminate_on_success && has_success);
    collector_->ResetEpisodes();
    actor.Reset(all_envs, agents::ResetScope::kEpisode, state);
    const agents::ActMode mode = config_.sample_evaluation ? agents::ActMode::kSample
                                                           : agents::ActMode::kDeterministic;
    std::vector<Totals> counted(num_tasks);
    int64_t short_tasks = num_tasks;
    while (short_tasks > 0) {
      step(state, mode, [&](const EpisodeRecord& r) {
        Totals& t = counted[r.env / per_task];
        if (t.episodes >= config_.evaluation_episodes) return;
        episodes.push_back({tasks_.tasks[r.env / per_task].name, round, true, t.episodes,
                            r.episode_return, r.length,
                            has_success ? std::optional<bool>(r.success) : std::nullopt});
        t.Add(r);
        if (t.episodes == config_.evaluation_episodes) --short_tasks;
      });
    }
    collector_->TerminateOnSuccess(false);
    for (int64_t t = 0; t < num_tasks; ++t) {
      success_sum[t] += counted[t].successes / static_cast<double>(counted[t].episodes);
      return_sum[t] += counted[t].returns / static_cast<double>(counted[t].episodes);
    }
  }

  MetaTestResult result;
  result.config = config_;
  const double rounds = static_cast<double>(config_.num_evals);
  for (int64_t t = 0; t < num_tasks; ++t) {
    MetaTestTaskResult r;
    r.task = tasks_.tasks[t].name;
    r.mean_return = return_sum[t] / rounds;
    if (has_success) r.success = success_sum[t] / rounds;
    r.pre_mean_return = pre[t].returns / static_cast<double>(pre[t].episodes);
    if (has_success) r.pre_success = pre[t].successes / static_cast<double>(pre[t].episodes);
    // an env's adaptation episodes and its task's evaluation episodes
    r.trial_return = r.pre_mean_return * static_cast<double>(config_.adaptation_episodes) +
                     r.mean_return * static_cast<double>(config_.evaluation_episodes);
    result.per_task.push_back(std::move(r));
  }
  result.AverageTasks(has_success, /*has_pre_adaptation=*/true);
  result.episodes = std::move(episodes);
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace manyworlds::experiments
