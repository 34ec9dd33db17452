#include "manyworlds/experiments/task_set.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"

namespace manyworlds::experiments {
namespace {

// Applies a task state on a scratch env, turning the env's complaint into a
// ConfigError that names the config entry.
void CheckState(Env& env, const TaskState& state, const std::string& where) {
  try {
    env.SetTaskState(state);
  } catch (const Error& e) {
    throw ConfigError(where + ": " + e.what());
  }
}

TaskState StateFromConfig(const nlohmann::json& json, const std::string& where) {
  try {
    return TaskState::FromJson(json);
  } catch (const Error& e) {
    throw ConfigError(where + ": " + e.what());
  }
}

// Makes names unique: the second "reach" becomes "reach#1".
void Deduplicate(std::vector<TaskSpec>& tasks) {
  std::map<std::string, int> count;
  for (const auto& t : tasks) ++count[t.name];
  std::map<std::string, int> seen;
  for (auto& t : tasks) {
    if (count[t.name] > 1) {
      const int k = seen[t.name]++;
      if (k > 0) {
        t.name += '#';
        t.name += std::to_string(k);
      }
    }
  }
}

}  // namespace

std::unique_ptr<Env> TaskSet::MakeEnv(int64_t task, const Registry& registry) const {
  return registry.Make(tasks.at(task).env_id, options);
}

nlohmann::json TaskSet::ToJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& t : tasks) {
    nlohmann::json states = nlohmann::json::array();
    for (const auto& v : t.variations) states.push_back(v.ToJson());
    list.push_back({{"name", t.name}, {"env_id", t.env_id}, {"variations", states}});
  }
  nlohmann::json json = {{"options", options}, {"tasks", list}};
  if (has_split()) {
    json["support_variations"] = support_variations;
    json["query_variations"] = query_variations;
  }
  return json;
}

int64_t TaskSet::Groups(int64_t task) const {
  return static_cast<int64_t>(tasks.at(task).variations.size()) /
         (support_variations + query_variations);
}

int64_t TaskSet::SupportVariation(int64_t group, int64_t k) const {
  return group * (support_variations + query_variations) + k % support_variations;
}

int64_t TaskSet::QueryVariation(int64_t group, int64_t k) const {
  return group * (support_variations + query_variations) + support_variations +
         k % query_variations;
}

TaskSet TaskSet::QueryVariations() const {
  if (!has_split()) throw Error("TaskSet::QueryVariations: the task set has no support/query split");
  TaskSet set;
  set.options = options;
  for (int64_t t = 0; t < size(); ++t) {
    TaskSpec spec{tasks[t].name, tasks[t].env_id, {}};
    for (int64_t g = 0; g < Groups(t); ++g) {
      for (int64_t k = 0; k < query_variations; ++k) {
        spec.variations.push_back(tasks[t].variations[QueryVariation(g, k)]);
      }
    }
    set.tasks.push_back(std::move(spec));
  }
  return set;
}

namespace {

// ConfigError unless every task's variations split into whole groups.
void CheckSplit(const TaskSet& set, const std::string& section) {
  const int64_t group = set.support_variations + set.query_variations;
  for (const TaskSpec& task : set.tasks) {
    const auto n = static_cast<int64_t>(task.variations.size());
    if (n % group != 0) {
      throw ConfigError("'" + section + ".support_variations' + 'query_variations' (" +
                        std::to_string(group) + ") must divide every task's variations; task " +
                        task.name + " has " + std::to_string(n));
    }
  }
}

}  // namespace

TaskSet TaskSet::FromJson(const nlohmann::json& json) {
  try {
    TaskSet set;
    set.options = json.at("options");
    for (const auto& t : json.at("tasks")) {
      TaskSpec spec{t.at("name").get<std::string>(), t.at("env_id").get<std::string>(), {}};
      for (const auto& v : t.at("variations")) spec.variations.push_back(TaskState::FromJson(v));
      if (spec.variations.empty()) throw Error("task '" + spec.name + "' has no variations");
      set.tasks.push_back(std::move(spec));
    }
    if (set.tasks.empty()) throw Error("no tasks");
    set.support_variations = json.value("support_variations", int64_t{0});
    set.query_variations = json.value("query_variations", int64_t{0});
    if (set.support_variations < 0 || set.query_variations < 0 ||
        (set.support_variations > 0) != (set.query_variations > 0)) {
      throw Error("support_variations and query_variations must both be 0 or both positive");
    }
    if (set.has_split()) CheckSplit(set, "tasks");
    return set;
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("malformed task list: ") + e.what());
  }
}

namespace {

TaskSet ResolveTaskList(const EnvSectionConfig& env, const Registry& registry) {
  TaskSet set;
  set.options = env.options;
  const auto& states = env.task_states;
  if (!env.tasks.empty()) {
    if (!states.empty() && states.size() != env.tasks.size()) {
      throw ConfigError("'env.task_states' has " + std::to_string(states.size()) +
                        " entries for " + std::to_string(env.tasks.size()) + " tasks");
    }
    for (size_t i = 0; i < env.tasks.size(); ++i) {
      auto made = registry.Make(env.tasks[i], env.options);
      TaskState state;
      if (states.empty()) {
        made->SeedTask(MixSeed(env.task_seed, i));
        state = made->SampleTaskState();
      } else {
        state = StateFromConfig(states[i], "env.task_states." + std::to_string(i));
      }
      CheckState(*made, state, "env.task_states." + std::to_string(i));
      set.tasks.push_back({env.tasks[i], env.tasks[i], {std::move(state)}});
    }
    Deduplicate(set.tasks);
    return set;
  }

  auto proto = registry.Make(env.id, env.options);
  if (!states.empty()) {
    if (env.num_tasks != 0 && env.num_tasks != static_cast<int64_t>(states.size())) {
      throw ConfigError("'env.num_tasks' is " + std::to_string(env.num_tasks) +
                        " but 'env.task_states' has " + std::to_string(states.size()) +
                        " entries");
    }
    for (size_t i = 0; i < states.size(); ++i) {
      const std::string where = "env.task_states." + std::to_string(i);
      TaskState state = StateFromConfig(states[i], where);
      CheckState(*proto, state, where);
      set.tasks.push_back({env.id + "/" + std::to_string(i), env.id, {std::move(state)}});
    }
    if (states.size() == 1) set.tasks[0].name = env.id;
    return set;
  }

  proto->SeedTask(env.task_seed);
  if (env.num_tasks == 0) {
    // the env's own task list (a benchmark: one group per task with its
    // variations), else a single sampled task
    std::vector<TaskGroup> groups = proto->EvaluationTasks();
    if (groups.empty()) {
      set.tasks.push_back({env.id, env.id, {proto->SampleTaskState()}});
      return set;
    }
    for (auto& group : groups) {
      if (group.states.empty()) continue;
      if (env.variations_per_task > 0 &&
          static_cast<int64_t>(group.states.size()) > env.variations_per_task) {
        group.states.resize(env.variations_per_task);
      }
      set.tasks.push_back({group.name, env.id, std::move(group.states)});
    }
    if (set.tasks.empty()) throw ConfigError("env '" + env.id + "' lists no tasks");
    Deduplicate(set.tasks);
    return set;
  }
  for (int64_t i = 0; i < env.num_tasks; ++i) {
    // one draw per task when variations_per_task <= 1: existing task sets keep their states
    std::vector<TaskState> states = {proto->SampleTaskState()};
    for (int64_t v = 1; v < env.variations_per_task; ++v) states.push_back(proto->SampleTaskState());
    set.tasks.push_back({env.num_tasks == 1 ? env.id : env.id + "/" + std::to_string(i), env.id,
                         std::move(states)});
  }
  return set;
}

}  // namespace

TaskSet ResolveTasks(const EnvSectionConfig& env, const Registry& registry, const std::string& section) {
  TaskSet set = ResolveTaskList(env, registry);
  set.support_variations = env.support_variations;
  set.query_variations = env.query_variations;
  if (set.has_split()) CheckSplit(set, section);
  return set;
}

EnvFacts FactsOf(const TaskSet& tasks, const std::function<const Env&(int64_t task)>& env_of) {
  EnvFacts facts;
  std::vector<std::string> info_fields;
  for (int64_t t = 0; t < tasks.size(); ++t) {
    const EnvSpec& spec = env_of(t).spec();
    const Space& action = spec.action_space;
    const std::string who = "env '" + spec.id + "' (task " + tasks.tasks[t].name + ")";
    for (size_t i = 0; action.is_box() && i < action.low().size(); ++i) {
      if (!std::isfinite(action.low()[i]) || !std::isfinite(action.high()[i])) {
        throw ConfigError(who + ": the action space must be bounded (policies act in [-1, 1], "
                          "scaled to the bounds), got " + action.ToString());
      }
    }
    const int64_t num_actions = action.is_box() ? 0 : action.n();
    if (spec.max_episode_steps <= 0) {
      throw ConfigError(who + " has no episode limit; set env.options.max_episode_steps");
    }
    if (t == 0) {
      facts.obs_dim = spec.env_obs_space.flat_size();
      facts.action_dim = action.flat_size();
      facts.num_actions = num_actions;
      if (action.is_box()) {
        facts.action_low = action.low();
        facts.action_high = action.high();
      }
      facts.info_size = spec.info_fields.size();
      facts.success_index = spec.InfoIndex("success");
      info_fields = spec.info_fields;
      if (spec.pixel_space.flat_size() > 0) facts.pixel_shape = spec.pixel_space.shape();
    } else if (spec.env_obs_space.flat_size() != facts.obs_dim ||
               action.flat_size() != facts.action_dim || num_actions != facts.num_actions ||
               (action.is_box() && (action.low() != facts.action_low ||
                                    action.high() != facts.action_high)) ||
               spec.info_fields != info_fields ||
               (spec.pixel_space.flat_size() > 0 ? spec.pixel_space.shape()
                                                 : std::vector<int64_t>()) != facts.pixel_shape) {
      throw ConfigError(who + " differs from task " + tasks.tasks[0].name +
                        " in observation size, action space, info fields or pixel frames");
    }
    facts.episode_length = std::max(facts.episode_length, spec.max_episode_steps);
  }
  return facts;
}

EnvFacts InspectEnvs(const TaskSet& tasks, const Registry& registry) {
  std::unique_ptr<Env> env;
  return FactsOf(tasks, [&](int64_t t) -> const Env& {
    env = tasks.MakeEnv(t, registry);
    return *env;
  });
}

void CheckEvalFacts(const EnvFacts& eval, const EnvFacts& train) {
  if (eval.obs_dim != train.obs_dim || eval.action_dim != train.action_dim ||
      eval.num_actions != train.num_actions) {
    throw ConfigError("eval_env: its tasks' observation or action spaces differ from env's (obs " +
                      std::to_string(eval.obs_dim) + " vs " + std::to_string(train.obs_dim) +
                      ", action " + std::to_string(eval.action_dim) + " vs " +
                      std::to_string(train.action_dim) + ")");
  }
  if (eval.pixel_shape != train.pixel_shape) {
    throw ConfigError("eval_env: its tasks' pixel frames (obs=pixels, pixel_width, pixel_height, "
                      "frame_stack) differ from env's");
  }
}

}  // namespace manyworlds::experiments
