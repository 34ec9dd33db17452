// Evaluation by the published multi-task protocol (the Meta-World paper's;
// MTRL's evaluate_vec_env_of_tasks):
//  - deterministic (mean) actions;
//  - an episode is a success if the env's `success` info field was 1 at any
//    step (not only at the end);
//  - per task: success rate and mean return over its episodes; overall: the
//    mean over tasks of both.
// Envs without a `success` field report success as absent (null) but still
// report returns.
//
// Episode e of task t runs with env seed MixSeed(MixSeed(seed, t), e) on the
// task's variation e mod (number of variations), so an evaluation depends only on the policy: the same
// checkpoint gives the same numbers during training and in `manyworlds eval`.
#ifndef MANYWORLDS_EXPERIMENTS_EVALUATION_EVALUATOR_H_
#define MANYWORLDS_EXPERIMENTS_EVALUATION_EVALUATOR_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "manyworlds/core/registry.h"
#include "manyworlds/experiments/loops/collector.h"
#include "manyworlds/experiments/task_set.h"

// Torch-free header (the Python bindings and env-only tools include it).
namespace at {
class Tensor;
}  // namespace at
namespace manyworlds::agents {
class Actor;
}  // namespace manyworlds::agents

namespace manyworlds::experiments {

// A rate that envs without `success` do not have, as results write it: a number or null.
inline nlohmann::json OptionalJson(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// One evaluation episode.
struct EpisodeResult {
  double episode_return = 0.0;
  int64_t length = 0;
  std::optional<bool> success;  // absent for envs without `success`
};

struct TaskEvalResult {
  std::string task;
  std::optional<double> success;  // success rate in [0, 1]; absent without `success`
  double mean_return = 0.0;
  double mean_length = 0.0;
  std::vector<EpisodeResult> episodes;  // in episode order (not in ToJson)
};

struct EvalResult {
  int64_t step = 0;  // env steps per task when it ran
  int64_t episodes_per_task = 0;
  std::vector<TaskEvalResult> per_task;
  std::optional<double> mean_success;
  double mean_return = 0.0;
  double wall_s = 0.0;

  // {"step", "episodes_per_task", "mean_success", "mean_return",
  //  "per_task": {name: {"success", "return", "length"}}, "wall_s"}
  nlohmann::json ToJson() const;
};

// obs (N, obs_dim) float32 and task indices (N) int64 -> actions (N,
// action_dim) in (-1, 1).
using PolicyFn = std::function<at::Tensor(const at::Tensor& obs, const at::Tensor& task)>;

// Seed stream of evaluation episodes (mixed with the run seed).
inline constexpr uint64_t kEvalSeedStream = 0x6576616c;  // "eval"

// An evaluation protocol: runs a policy on a run's tasks and reports
// per-task results. The multi-task protocol (Evaluator) is the one today;
// the meta-test protocol (explore, adapt, evaluate on held-out tasks) will be
// another implementation.
class EvaluationProtocol {
 public:
  virtual ~EvaluationProtocol() = default;
  virtual EvalResult Run(agents::Actor& actor) = 0;
};

// The multi-task protocol.
class Evaluator : public EvaluationProtocol {
 public:
  // Builds the evaluation envs (a wave of up to 64 envs in all, split evenly
  // between tasks). `facts`: the tasks' facts, where the caller has them
  // (else they are read from the evaluation envs). Throws ConfigError as
  // FactsOf does.
  Evaluator(const TaskSet& tasks, const Registry& registry, int64_t episodes_per_task,
            uint64_t seed, int num_threads, const EnvFacts* facts = nullptr);
  ~Evaluator();

  EvalResult Run(const PolicyFn& policy);
  // Deterministic actions of an actor, told where its episodes begin.
  EvalResult Run(agents::Actor& actor) override;

  int64_t episodes_per_task() const { return episodes_; }
  // With on, episodes end at the first success (Meta-World v3's evaluation
  // toggles terminate_on_success); envs without a success field ignore it.
  void TerminateOnSuccess(bool on);
  const EnvFacts& facts() const { return facts_; }
  // Env i of the evaluation (PolicyActor's envs).
  Env& env(int64_t i) { return collector_->env(i); }

 private:
  // What the envs did after a step: the observations acted on (N, obs_dim),
  // policy actions (N, action_dim), rewards and episode-end flags (N each).
  using ObserveFn = std::function<void(const at::Tensor& obs, const at::Tensor& actions,
                                       const float* rewards, const float* ended)>;
  // Run, calling new_episodes before each batch of episodes after the first
  // (every slot starts a new episode, on another variation, there) and
  // observe (if set) after every step.
  EvalResult RunEpisodes(const PolicyFn& policy, const std::function<void()>& new_episodes,
                         const ObserveFn& observe = {});

  const TaskSet& tasks_;
  EnvFacts facts_;
  int64_t episodes_;
  uint64_t seed_;
  int64_t slots_;  // envs per task in one wave
  std::unique_ptr<Collector> collector_;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_EVALUATION_EVALUATOR_H_
