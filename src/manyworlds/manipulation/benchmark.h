// Meta-World-style benchmarks over the Sawyer tasks: MT1, MT10, MT25, MT50,
// ML1, ML10, ML25, ML45 (splits as Meta-World v3's env_dict.py, variations
// as its benchmark classes in metaworld/__init__.py; docs/fidelity.md says
// how our seeding differs).
//
// A benchmark is itself a multi-task env. Its tasks are pairs (task,
// variation): every task has `num_variations` (50) variations (object and
// goal positions) drawn once, at construction, from the benchmark seed and
// nothing else. The train split draws from the seed, the test split from
// seed + 1, so ML1's test variations differ from its train ones. A task's
// variations depend only on the seed and the task's name, so push has the
// same 50 train variations in MT1, MT10 and ML10. (In v3 a task's goals
// depend on its position in the benchmark's list; here they do not.)
//
// Task state (self-contained: the member state is embedded and checked):
//   {"env": "mt10", "params": {"task": "push", "variation": 7,
//                              "state": <push's own task state>}}
// Sampling picks a task, then a variation, uniformly with the task
// generator; SeedTask changes which (task, variation) pairs come up, never
// the variations themselves.
//
// Observation: the member's 39 values (the union of the members' bounds).
// MT benchmarks show the goal and give the task index as task observation
// (Discrete(num_tasks)); with the option task_id_in_obs=true the registry
// also appends it to the observation as a one-hot vector (AppendTaskOneHot;
// off by default, as v3's use_one_hot). ML benchmarks hide the goal and have
// no task observation: the agent must find out the task by acting.
//
// EvaluationTasks(): one group per task with all its variations.
#ifndef MANYWORLDS_MANIPULATION_BENCHMARK_H_
#define MANYWORLDS_MANIPULATION_BENCHMARK_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "manyworlds/core/env.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

enum class BenchmarkSplit { kTrain, kTest };

struct BenchmarkConfig {
  std::string id;                  // e.g. "mt10", "ml1-push"
  std::vector<std::string> tasks;  // registry ids of the member tasks, in one-hot order
  bool meta = false;               // ML: goal hidden, no task observation
  BenchmarkSplit split = BenchmarkSplit::kTrain;
  uint64_t seed = 0;               // the benchmark seed
  int num_variations = 50;
  // Every member's reward version; v1 needs every member to have it.
  RewardVersion reward_version = RewardVersion::kV2;
};

// The published splits, as Meta-World v3's env_dict.py
// lists them: a task's position is its one-hot index.
struct BenchmarkSplits {
  std::string id;           // registry id: "mt10", "ml45", ...
  std::string description;  // one line for `manyworlds envs`
  bool meta = false;        // ML: goal hidden, no task observation, a test split
  std::vector<std::string> train;
  std::vector<std::string> test;  // ML only
};
// mt10, mt25, mt50, ml10, ml25, ml45 (MT1/ML1 take their task as an option).
const std::vector<BenchmarkSplits>& PublishedBenchmarks();
// Throws ConfigError for an id not in PublishedBenchmarks().
const BenchmarkSplits& PublishedBenchmark(const std::string& id);
// All 50 tasks in v3's order (ALL_V3_ENVIRONMENTS; MT50's one-hot order).
std::vector<std::string> Mt50Tasks();
std::vector<std::string> Mt10Tasks();
std::vector<std::string> Ml10TrainTasks();
std::vector<std::string> Ml10TestTasks();

class Benchmark : public Env, public sim::SceneSource, public ScriptedPolicySource {
 public:
  // Throws ConfigError for an unknown task id, no tasks or a bad count.
  explicit Benchmark(BenchmarkConfig config);

  const BenchmarkConfig& config() const { return config_; }
  int num_tasks() const { return static_cast<int>(config_.tasks.size()); }
  const std::string& task_name(int task) const { return config_.tasks.at(task); }
  const std::vector<TaskState>& variations(int task) const { return variations_.at(task); }
  // The member task and the variation of the current task (-1 before one).
  int active_task() const { return active_task_; }
  int active_variation() const { return active_variation_; }
  // The member task, built on first use (see members_).
  const SawyerTask& member(int task) const { return Member(task); }

  // The task state of one (task, variation) pair.
  TaskState VariationState(int task, int variation) const;
  std::vector<TaskGroup> EvaluationTasks() const override;

  void SetMaxEpisodeSteps(int64_t max_episode_steps) override;

  // SceneSource: the active member's scene (none before the first task
  // state) and MJCF (EpisodeStateError before the first task state).
  sim::Scene ActiveScene() const override;
  void SaveSceneXml(const std::string& path) const override;
  // ScriptedPolicySource: the members' scripted policies, each used while
  // its task is active; privileged like SawyerTask's.
  std::unique_ptr<Policy> CreateScriptedPolicy() const override;

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  Benchmark(BenchmarkConfig config, std::vector<std::unique_ptr<SawyerTask>> members);

  SawyerTask& Member(int task) const;

  BenchmarkConfig config_;
  // Built to draw the variations and the spec, then released: a member is
  // rebuilt when a task state first selects it, so an env holds only the
  // models it runs (a training run makes one mt50 env per task: 50 models,
  // not 2,500). A member's task state is all it keeps, so rebuilding it
  // changes nothing.
  mutable std::vector<std::unique_ptr<SawyerTask>> members_;
  std::vector<std::vector<TaskState>> variations_;
  std::vector<float> member_task_obs_;  // scratch for the member's goal
  int active_task_ = -1;
  int active_variation_ = -1;
};

// Registers mt10, ml10, mt1 and ml1 (family "benchmark"); every task they
// name must be registered by RegisterManipulationSuite.
void RegisterBenchmarks(Registry& registry);

// The Sawyer task that runs the current task of `env` (a task, a benchmark's
// active member, either behind wrappers), or nullptr if there is none (no
// task set yet, or not a manipulation env).
const SawyerTask* ActiveSawyerTask(const Env& env);

// The scripted policy for a Sawyer task, a benchmark, or either behind
// wrappers that keep the first 39 observation values (CreateScriptedPolicy
// of the one found). `env` must outlive the policy. Throws ConfigError for
// other envs.
std::unique_ptr<Policy> MakeScriptedPolicyFor(const Env& env);

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_BENCHMARK_H_
