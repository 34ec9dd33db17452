// Where envs meet learners, the one episode engine: a batched executor over a
// task set's envs, their seeding (training rounds, or the episodes an
// evaluation protocol asks for), action mapping and episode accounting. The
// training loops, the multi-task evaluator and the meta-test protocol all
// step their envs through a Collector.
//
// Envs: envs_per_task per task, env i runs task i / envs_per_task. Rounds:
// at the start of round r every env is re-seeded from (seed, r, env) and
// reset on a variation of its task drawn from the same stream, so nothing of
// a previous round carries over and a run can be checkpointed at any round
// boundary and resumed exactly.
//
// Actions: policies act in their own units (agents/actor.h); Step clips Box
// actions to [-1, 1] and scales them to the env's bounds, and passes
// Discrete indices through.
#ifndef MANYWORLDS_EXPERIMENTS_LOOPS_COLLECTOR_H_
#define MANYWORLDS_EXPERIMENTS_LOOPS_COLLECTOR_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/core/executor.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/experiments/loops/episode_tracker.h"
#include "manyworlds/experiments/task_set.h"

namespace manyworlds::experiments {

// Training statistics of the episodes that ended in a stretch of steps.
struct EpisodeTotals {
  double return_sum = 0.0;
  double success_sum = 0.0;
  int64_t episodes = 0;
  void Add(const EpisodeRecord& r) {
    return_sum += r.episode_return;
    success_sum += r.success ? 1.0 : 0.0;
    ++episodes;
  }
  void Add(const EpisodeTotals& other) {
    return_sum += other.return_sum;
    success_sum += other.success_sum;
    episodes += other.episodes;
  }
  // train_episodes, train_return and train_success (null where undefined).
  void WriteTo(nlohmann::json& row, bool has_success) const {
    row["train_episodes"] = episodes;
    row["train_return"] =
        episodes > 0 ? nlohmann::json(return_sum / episodes) : nlohmann::json();
    row["train_success"] = episodes > 0 && has_success ? nlohmann::json(success_sum / episodes)
                                                       : nlohmann::json();
  }
};

class Collector {
 public:
  // Builds envs_per_task envs per task (each env once: the task set's facts
  // are read from them, see FactsOf, which says what it throws).
  Collector(const TaskSet& tasks, const Registry& registry, int64_t envs_per_task,
            int num_threads);
  // The same with the tasks' facts known.
  Collector(const TaskSet& tasks, const Registry& registry, const EnvFacts& facts,
            int64_t envs_per_task, int num_threads);

  int64_t num_envs() const { return num_envs_; }
  int64_t envs_per_task() const { return envs_per_task_; }
  const EnvFacts& facts() const { return facts_; }
  // Task of each env, (num_envs) values in [0, num_tasks).
  const std::vector<int64_t>& env_tasks() const { return env_tasks_; }
  // Variation of its task each env runs in the current round (index into
  // TaskSpec::variations; 0 before the first BeginRound).
  const std::vector<int64_t>& env_variations() const { return env_variations_; }
  BatchedExecutor& executor() { return *exec_; }

  // With rounds_per_trial > 1, rounds r and r' with the same
  // r / rounds_per_trial keep each env on the same variation (a trial of
  // meta-RL); the env seeds still change every round. With a support/query
  // split (TaskSet::has_split) a trial keeps each env on one group instead:
  // its first support_rounds rounds run support variations of the group,
  // the others its query variations, each round's drawn from the round's
  // stream.
  void BeginRound(uint64_t seed, int64_t round, int64_t rounds_per_trial = 1,
                  int64_t support_rounds = 0);
  // Env i starts a new episode on variation v of its task at once, its
  // random streams going on (a trial that changes variation between
  // episodes). Call between steps, not inside CountEpisodes' callback.
  void StartEpisode(int64_t env, int64_t variation);
  // Starts a new episode in every env as `start(env)` says: its dynamics and
  // task seeds and which of its task's variations it runs (modulo their
  // number). The evaluation protocols seed their episodes this way.
  struct EnvStart {
    uint64_t seed = 0;
    uint64_t task_seed = 0;
    int64_t variation = 0;
  };
  void BeginEpisodes(const std::function<EnvStart(int64_t env)>& start);
  // Starts a new episode in every env on its current task variation, each
  // env's random streams going on (a Gymnasium vector env's reset()).
  void ResetEpisodes();
  // With on, an episode also ends at its first success step (Meta-World's
  // terminate_on_success): CountEpisodes reports it and the env starts its
  // next episode at once, as auto-reset does after an ended episode.
  void TerminateOnSuccess(bool on);
  // With on, Step and StepEnvs take actions in the env's units and pass them
  // on unchanged (Actor::ActsInEnvUnits); off (the default), in the policy's.
  void ActionsInEnvUnits(bool on) { env_units_ = on; }
  // Env i of the executor (its task, for policies that read it).
  Env& env(int64_t i) { return exec_->env(static_cast<int>(i)); }
  // Current observations (num_envs x obs_dim); valid until the next Step.
  std::span<const float> observations() const { return exec_->env_obs(); }
  // What a policy acts on, viewing the executor's buffers (valid until the
  // next Step): the pixel frames (num_envs, C, H, W) uint8 with obs=pixels,
  // else the observations (num_envs, obs_dim) float32.
  torch::Tensor PolicyObservations() const;
  // Steps every env with one row of policy actions each (num_envs x
  // action_dim) and accounts the episodes that ended into `totals`.
  void Step(std::span<const float> policy_actions, EpisodeTotals& totals);
  // The same in two halves, for callers that look at a step's outcome
  // (executor().rewards(), ...) before its episodes are counted: StepEnvs
  // steps, CountEpisodes calls on_end(record) for each env whose episode
  // ended, in env order (the env then runs its next episode).
  void StepEnvs(std::span<const float> policy_actions);
  template <class OnEnd>
  void CountEpisodes(OnEnd&& on_end) {
    const auto terminated = exec_->terminated();
    const auto truncated = exec_->truncated();
    tracker_.Step(exec_->rewards(), terminated, truncated, exec_->info(),
                  [&](const EpisodeRecord& r) {
                    on_end(r);
                    // ended at success: the executor did not reset it
                    if (!terminated[r.env] && !truncated[r.env]) succeeded_.push_back(r.env);
                  });
    RestartSucceeded();
  }

 private:
  Collector(const TaskSet& tasks, std::vector<std::unique_ptr<Env>> envs,
            const EnvFacts* facts, int64_t envs_per_task, int num_threads);
  void RestartSucceeded();

  const TaskSet& tasks_;
  EnvFacts facts_;
  int64_t envs_per_task_;
  int64_t num_envs_;
  std::vector<int64_t> env_tasks_;
  std::vector<int64_t> env_variations_;
  std::unique_ptr<BatchedExecutor> exec_;
  EpisodeTracker tracker_;
  std::vector<int64_t> succeeded_;  // envs whose episode ended at success this step
  std::vector<float> env_actions_;
  bool env_units_ = false;
};

// Maps policy actions to env actions: Box rows clipped to [-1, 1] and scaled
// to [low, high]; Discrete indices copied.
void PolicyToEnvActions(const float* policy, int64_t rows, const EnvFacts& facts, float* out);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_LOOPS_COLLECTOR_H_
