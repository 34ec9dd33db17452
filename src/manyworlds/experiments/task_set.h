// The tasks of a run: which env each task runs on and its fixed task state.
//
// Resolved once from the env section of the config and stored in the run
// directory (tasks.json), so that evaluation and resumed runs use exactly the
// training tasks even if a task sampler changes later. As in MTRL on
// Meta-World, the task states are fixed for the whole run. A task may have
// several variations (a benchmark task's object and goal positions): each
// training episode runs on one drawn uniformly, and evaluation episode e of a
// task runs on variation e mod (number of variations), so evaluating with as
// many episodes as variations covers each once (Meta-World+'s MT protocol).
#ifndef MANYWORLDS_EXPERIMENTS_TASK_SET_H_
#define MANYWORLDS_EXPERIMENTS_TASK_SET_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/env.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/core/task_state.h"

namespace manyworlds::experiments {

// The env section of a training config (train_config.h documents the keys).
struct EnvSectionConfig {
  std::string id;                  // one env id (tasks empty), or
  std::vector<std::string> tasks;  // one env id per task
  int64_t num_tasks = 0;           // with id; 0 = the env's task groups, or 1
  int64_t variations_per_task = 0; // 0 = all of a group's states
  nlohmann::json task_states = nlohmann::json::array();  // explicit, one per task
  nlohmann::json options = nlohmann::json::object();     // registry options
  int64_t envs_per_task = 1;
  uint64_t task_seed = 0;
  // The support/query split (both 0: none). Each task's variations come in
  // groups (layouts) of support + query consecutive ones: meta-learners
  // adapt on a group's first `support_variations` and are trained and scored
  // on its other `query_variations` (CS330's box-world protocol).
  int64_t support_variations = 0;
  int64_t query_variations = 0;
};

struct TaskSpec {
  std::string name;    // unique, for tables and metric keys ("point-nav/1", "reach")
  std::string env_id;  // registry id
  std::vector<TaskState> variations;  // >= 1; one is applied before every episode
};

struct TaskSet {
  std::vector<TaskSpec> tasks;
  nlohmann::json options = nlohmann::json::object();  // registry options of every env
  // The support/query split (EnvSectionConfig); both 0 without one.
  int64_t support_variations = 0;
  int64_t query_variations = 0;

  int64_t size() const { return static_cast<int64_t>(tasks.size()); }
  bool has_split() const { return support_variations > 0; }
  // With a split: task t's groups, and the variation of group g that is
  // its k-th support (query) one, k taken modulo their number.
  int64_t Groups(int64_t task) const;
  int64_t SupportVariation(int64_t group, int64_t k) const;
  int64_t QueryVariation(int64_t group, int64_t k) const;
  // The same tasks with only their query variations (no split): what
  // methods that do not adapt are scored on.
  TaskSet QueryVariations() const;
  // Makes a fresh env of task i (its task state not yet applied).
  std::unique_ptr<Env> MakeEnv(int64_t task, const Registry& registry) const;

  nlohmann::json ToJson() const;
  // Throws Error on malformed JSON.
  static TaskSet FromJson(const nlohmann::json& json);
};

// Resolves the env section (see train_config.h): makes the envs, draws or
// validates the task states. Throws ConfigError for unknown ids or options,
// or task states an env rejects.
// `section` names the config section in errors.
TaskSet ResolveTasks(const EnvSectionConfig& env, const Registry& registry,
                     const std::string& section = "env");

// Facts shared by every env of a task set, checked to agree between tasks.
struct EnvFacts {
  int64_t obs_dim = 0;         // env observation size (the learner's input)
  int64_t action_dim = 0;      // Box size, 1 for Discrete
  int64_t num_actions = 0;     // > 0: a Discrete(num_actions) action space
  std::vector<float> action_low, action_high;  // finite Box bounds (empty for Discrete)
  size_t info_size = 0;        // info fields per step
  int64_t episode_length = 0;  // the largest max_episode_steps (> 0)
  int success_index = -1;      // index of the "success" info field, or -1
  // Shape of the pixel observation (obs=pixels: channels, height, width);
  // empty without pixels.
  std::vector<int64_t> pixel_shape;
  int64_t pixel_size() const {
    int64_t n = pixel_shape.empty() ? 0 : 1;
    for (const int64_t d : pixel_shape) n *= d;
    return n;
  }
};

// The facts of a task set, read from one env of each task (`env_of(t)`: the
// caller's, so that no env is built only to be looked at). Throws
// ConfigError if an env has an unbounded Box action space, no episode limit,
// or spaces that differ between tasks. Which action spaces an algorithm
// accepts is the algorithm's check (algorithms.h).
EnvFacts FactsOf(const TaskSet& tasks, const std::function<const Env&(int64_t task)>& env_of);
// FactsOf on one env built per task, for callers that step no envs.
EnvFacts InspectEnvs(const TaskSet& tasks, const Registry& registry);

// ConfigError unless the held-out tasks (`eval`) present the spaces the
// policy was trained on (`train`).
void CheckEvalFacts(const EnvFacts& eval, const EnvFacts& train);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_TASK_SET_H_
