// The meta-test protocols (MetaTestConfig::protocol).
//
// metalearning_evaluation (the default) is Meta-World v3's
// metaworld/evaluation.py::metalearning_evaluation, parameter by parameter:
// meta_batch_size envs, meta_batch_size / T per held-out task (T tasks);
// task t's first total_tasks_per_cls variations (goals; all if 0) are dealt
// to its envs in turn (env j gets variations j, j + E, j + 2E, ..., as v3
// splits a class's tasks tasks[j::E]; v3 also asserts an even split, which
// its documented setup, 40 goals per ML10/ML45 test task, meets). num_evals rounds, each:
//  1. every env picks its goal for the round from its own list
//     (task_select: random, with replacement, or pseudorandom: through the
//     list in a shuffled order, reshuffled at its end) and starts on it;
//     the actor starts afresh (Actor::Initial, v3's agent.init());
//  2. adaptation_steps times: every env starts a new episode, all envs
//     step in lockstep, sampling, the actor seeing every step, until every
//     env has ended adaptation_episodes episodes (an env that has may run
//     on, as in v3's vector loop); then Actor::Adapt;
//  3. evaluation (v3's evaluation(agent, envs, evaluation_episodes)):
//     every env starts a new episode; episodes end at the first success
//     (terminate_on_success) or the time limit, and the first
//     evaluation_episodes episodes of each task to end, in the order they
//     end (envs in index order within a step), are its episodes: its success
//     rate and mean return for the round. Envs run on until every task has
//     its episodes. Deterministic actions unless sample_evaluation.
// Per task: the mean over rounds; overall: the mean over tasks. Before
// adaptation: the first adaptation phase's first adaptation_episodes
// episodes of every env. Env seeds: env i starts round r with
// MixSeed(MixSeed(seed, r), i); later episodes go on with its streams.
//
// per_variation: for every test task and each of its variations, one trial
// in one env:
//  1. exploration_episodes episodes with the actor sampling (the
//     exploration policy), the actor seeing every step's outcome;
//  2. Actor::Adapt;
//  3. evaluation_episodes episodes with the adapted actor (deterministic
//     actions unless sample_evaluation).
// With a support/query split of the held-out tasks (TaskSet::has_split),
// trial v runs group v mod (groups): its k-th exploration episode on the
// group's k-th support variation and its k-th evaluation episode on its
// k-th query variation (k modulo their numbers); metalearning_evaluation
// refuses such tasks.
// An episode is a success if `success` > 0.5 at any step. Per task: the
// success rate and mean return of the evaluation episodes (after
// adaptation) and of the exploration episodes (before), and the mean total
// return of a trial (the RL2 bandit score).
//
// Phases run in lockstep: an env that has finished its episodes of a phase
// waits, its actor state frozen, until every env has; each phase starts
// with a fresh episode. Sampled actions come from a generator of the
// protocol's seed (ActorState::generator), so a meta-test during training and
// `eval --protocol meta-test` on the same checkpoint give the same numbers. Env seeds: trial v of task t uses MixSeed(MixSeed(
// seed, t), v) and runs on variation v mod (number of variations).
#ifndef MANYWORLDS_EXPERIMENTS_EVALUATION_META_TEST_PROTOCOL_H_
#define MANYWORLDS_EXPERIMENTS_EVALUATION_META_TEST_PROTOCOL_H_

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "manyworlds/core/registry.h"
#include "manyworlds/experiments/evaluation/evaluator.h"
#include "manyworlds/experiments/task_set.h"
#include "manyworlds/experiments/train_config.h"

namespace manyworlds::experiments {

// Seed streams of meta-test trials on the held-out tasks and of meta-train
// trials (the same protocol on the training tasks), mixed with the run seed.
inline constexpr uint64_t kMetaTestSeedStream = 0x6d657461;   // "meta"
inline constexpr uint64_t kMetaTrainSeedStream = 0x6d747261;  // "mtra"

// A held-out task's goals in metalearning_evaluation: its first
// total_tasks_per_cls variations (all if 0), as v3's make_ml_envs takes
// tasks[:total_tasks_per_cls].
int64_t GoalsOf(const TaskSpec& task, const MetaTestConfig& config);

// One line naming the protocol and its parameters, for tables and logs.
std::string DescribeProtocol(const MetaTestConfig& config);
// The protocol's parameters of a MetaTestResult::ToJson (one that names no
// protocol, from before 2026-11-27, was per_variation).
MetaTestConfig MetaTestConfigOf(const nlohmann::json& result);

struct MetaTestTaskResult {
  std::string task;
  std::optional<double> success;      // evaluation episodes
  double mean_return = 0.0;
  std::optional<double> pre_success;  // exploration episodes
  double pre_mean_return = 0.0;
  double trial_return = 0.0;          // mean total return of a trial
};

// One episode of a meta-test trial.
struct MetaTestEpisode {
  std::string task;
  int64_t trial = 0;     // the trial's index within its task
  bool evaluation = false;  // false: exploration (before adaptation)
  int64_t index = 0;     // within its phase
  double episode_return = 0.0;
  int64_t length = 0;
  std::optional<bool> success;
};

struct MetaTestResult {
  int64_t step = 0;
  MetaTestConfig config;
  std::vector<MetaTestTaskResult> per_task;
  std::optional<double> success_rate;  // mean over tasks
  double mean_return = 0.0;
  std::optional<double> pre_adaptation_success_rate;
  double pre_adaptation_return = 0.0;
  double trial_return = 0.0;
  double wall_s = 0.0;
  // Every episode, in the order they ended (not part of ToJson).
  std::vector<MetaTestEpisode> episodes;

  // {"step", "success_rate", "return", "pre_adaptation_success_rate",
  //  "pre_adaptation_return", "trial_return", "protocol", the protocol's
  //  parameters (MetaTestConfig's keys), "episodes_per_task" (evaluation
  //  episodes per task in all),
  //  "per_task": {name: {"success", "return", "pre_adaptation_success",
  //                      "pre_adaptation_return", "trial_return"}}, "wall_s"}
  nlohmann::json ToJson() const;
  // The evaluation episodes as a multi-task result (the trainer's tables).
  EvalResult AsEvalResult() const;
  // Sets the means over per_task's tasks: returns always, success rates
  // where the envs report success, the pre-adaptation one where episodes
  // ran before adaptation.
  void AverageTasks(bool has_success, bool has_pre_adaptation);
};

class MetaTestProtocol : public EvaluationProtocol {
 public:
  // Builds one env per trial, in waves of at most 64. Throws ConfigError as
  // FactsOf does, or on a bad config. `facts`: the tasks' facts, where the
  // caller has them (else they are read from the protocol's envs).
  MetaTestProtocol(const TaskSet& test_tasks, const Registry& registry,
                   const MetaTestConfig& config, uint64_t seed, int num_threads,
                   const EnvFacts* facts = nullptr);
  ~MetaTestProtocol();

  MetaTestResult RunMetaTest(agents::Actor& actor);
  const EnvFacts& facts() const { return facts_; }
  // Whether the tasks are held out from training (the trainer's meta-test;
  // false for the same protocol on the training tasks): actors are told so
  // (ActorState::held_out_tasks).
  void SetHeldOut(bool held_out) { held_out_ = held_out; }
  // Env i of the protocol (PolicyActor's envs).
  Env& env(int64_t i) { return collector_->env(i); }
  EvalResult Run(agents::Actor& actor) override { return RunMetaTest(actor).AsEvalResult(); }

 private:
  MetaTestResult RunPerVariation(agents::Actor& actor);
  MetaTestResult RunMetalearningEvaluation(agents::Actor& actor);

  const TaskSet& tasks_;
  MetaTestConfig config_;
  EnvFacts facts_;
  uint64_t seed_;
  int64_t slots_;  // per_variation: envs per task in one wave; else envs per task
  bool held_out_ = false;
  std::unique_ptr<Collector> collector_;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_EVALUATION_META_TEST_PROTOCOL_H_
