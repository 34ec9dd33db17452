#include "manyworlds/experiments/train_config.h"

#include <algorithm>

#include <cmath>
#include <string>

#include "manyworlds/agents/sac/sac_config.h"
#include "manyworlds/config/override.h"
#include "manyworlds/config/reader.h"
#include "manyworlds/config/yaml.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/limits.h"
#include "manyworlds/experiments/algorithms.h"

namespace manyworlds::experiments {
namespace {

// The full default tree for an algorithm, so that dotted overrides can name
// any of its keys.
nlohmann::json DefaultTree(const std::string& algo) {
  TrainConfig defaults;
  defaults.agent = DefaultAgentConfig(algo);
  return defaults.ToJson();
}

// agent.algo as the file and the overrides set it (the last override wins).
std::string ChosenAlgo(const nlohmann::json& file, const std::vector<std::string>& overrides) {
  std::string algo = "sac";
  if (file.is_object() && file.contains("agent") && file["agent"].is_object() &&
      file["agent"].contains("algo")) {
    const nlohmann::json& value = file["agent"]["algo"];
    if (!value.is_string()) {
      throw ConfigError("'agent.algo' must be a string, got " + value.dump());
    }
    algo = value.get<std::string>();
  }
  constexpr std::string_view kKey = "agent.algo=";
  for (const std::string& o : overrides) {
    if (o.rfind(kKey, 0) == 0) algo = o.substr(kKey.size());
  }
  return algo;
}

nlohmann::json MetaTestJson(MetaTestConfig config) {
  nlohmann::json out = nlohmann::json::object();
  config.VisitFields([&](const char* key, const auto& value) { out[key] = value; });
  return out;
}

// A meta_test key the file or an override sets to other than its default
// that the chosen protocol has no use for is a ConfigError (a config written
// for the per_variation protocol, the only one before 2026-11-27, must say
// so; a whole config.json, defaults included, passes).
void CheckMetaTestKeys(const nlohmann::json& file, const std::vector<std::string>& overrides,
                       const MetaTestConfig& meta_test) {
  std::vector<std::string> set;
  if (file.is_object() && file.contains("meta_test") && file["meta_test"].is_object()) {
    for (const auto& [key, value] : file["meta_test"].items()) set.push_back(key);
  }
  for (const std::string& o : overrides) {
    if (o.rfind("meta_test.", 0) == 0) set.push_back(o.substr(10, o.find('=') - 10));
  }
  const nlohmann::json defaults = MetaTestJson(MetaTestConfig{});
  const nlohmann::json chosen = MetaTestJson(meta_test);
  for (const std::string& key : set) {
    const std::string_view owner = MetaTestConfig::ProtocolOf(key);
    if (!owner.empty() && owner != meta_test.protocol && chosen[key] != defaults[key]) {
      throw ConfigError("'meta_test." + key + "' is not a key of the " + meta_test.protocol +
                        " protocol; set meta_test.protocol to " + std::string(owner) +
                        " to use it");
    }
  }
}

[[noreturn]] void Bad(const std::string& key, const std::string& what) {
  throw ConfigError("'" + key + "' " + what);
}

void CheckSplitKeys(const EnvSectionConfig& env, const std::string& section) {
  if (env.support_variations < 0 || env.query_variations < 0 ||
      (env.support_variations > 0) != (env.query_variations > 0)) {
    Bad(section + ".support_variations",
        "and '" + section + ".query_variations' must both be 0 (no split) or both >= 1, got " +
            std::to_string(env.support_variations) + " and " +
            std::to_string(env.query_variations));
  }
}

}  // namespace

TrainConfig TrainConfig::FromJson(const nlohmann::json& json) {
  TrainConfig c;
  ConfigReader root(json);
  {
    ConfigReader r = root.Section("env");
    r.Read("id", c.env.id);
    r.Read("tasks", c.env.tasks);
    r.Read("num_tasks", c.env.num_tasks);
    r.Read("variations_per_task", c.env.variations_per_task);
    r.Read("task_states", c.env.task_states);
    r.Read("options", c.env.options);
    r.Read("envs_per_task", c.env.envs_per_task);
    r.Read("task_seed", c.env.task_seed);
    r.Read("support_variations", c.env.support_variations);
    r.Read("query_variations", c.env.query_variations);
    r.Finish();
    if (c.env.task_states.is_null()) c.env.task_states = nlohmann::json::array();
    if (c.env.options.is_null()) c.env.options = nlohmann::json::object();
  }
  {
    ConfigReader r = root.Section("eval_env");
    const bool given = json.is_object() && json.contains("eval_env") && !json["eval_env"].is_null();
    if (given) {
      // the env section with the keys given here replaced
      EnvSectionConfig e = c.env;
      const nlohmann::json& section = json["eval_env"];
      if (section.is_object() && (section.contains("id") || section.contains("tasks"))) {
        e.id.clear();
        e.tasks.clear();
      }
      r.Read("id", e.id);
      r.Read("tasks", e.tasks);
      r.Read("num_tasks", e.num_tasks);
      r.Read("variations_per_task", e.variations_per_task);
      r.Read("task_states", e.task_states);
      r.Read("options", e.options);
      r.Read("task_seed", e.task_seed);
      r.Read("support_variations", e.support_variations);
      r.Read("query_variations", e.query_variations);
      if (e.task_states.is_null()) e.task_states = nlohmann::json::array();
      if (e.options.is_null()) e.options = nlohmann::json::object();
      c.eval_env = std::move(e);
    }
    r.Finish();
  }
  {
    ConfigReader r = root.Section("meta_test");
    // run directories from before 2026-11-27 name no protocol: theirs was per_variation
    if (json.is_object() && json.contains("meta_test") && json["meta_test"].is_object() &&
        !json["meta_test"].contains("protocol")) {
      c.meta_test.protocol = kPerVariation;
    }
    c.meta_test.VisitFields([&](const char* key, auto& value) { r.Read(key, value); });
    r.Finish();
  }
  {
    ConfigReader r = root.Section("agent");
    if (json.is_object() && json.contains("agent")) {
      c.agent = ReadAgentConfig(json["agent"]);
      nlohmann::json ignored;
      for (const auto& [key, value] : json["agent"].items()) r.Read(key, ignored);
    }
    r.Finish();
  }
  {
    ConfigReader r = root.Section("replay");
    r.Read("capacity", c.replay.capacity);
    r.Read("sampling", c.replay.sampling);
    r.Finish();
  }
  {
    ConfigReader r = root.Section("experiment");
    auto& e = c.experiment;
    r.Read("seed", e.seed);
    r.Read("steps_per_task", e.steps_per_task);
    r.Read("warmup_steps", e.warmup_steps);
    r.Read("updates_per_step", e.updates_per_step);
    r.Read("batch_size", e.batch_size);
    r.Read("eval_every", e.eval_every);
    r.Read("eval_episodes", e.eval_episodes);
    r.Read("eval_terminate_on_success", e.eval_terminate_on_success);
    r.Read("num_threads", e.num_threads);
    r.Read("checkpoint_every", e.checkpoint_every);
    r.Read("keep_checkpoints", e.keep_checkpoints);
    r.Read("run_dir", e.run_dir);
    r.Read("init_from", e.init_from);
    r.Finish();
  }
  root.Finish();
  return c;
}

TrainConfig TrainConfig::Load(const std::optional<std::filesystem::path>& file,
                              const std::vector<std::string>& overrides) {
  nlohmann::json from_file;
  if (file) from_file = LoadYamlFile(*file);
  nlohmann::json tree = DefaultTree(ChosenAlgo(from_file, overrides));
  if (file) {
    if (!from_file.is_null() && !from_file.is_object()) {
      throw ConfigError(file->string() + ": the top level must be a mapping");
    }
    // read the file alone first so that unknown keys are reported against it
    try {
      FromJson(from_file);
    } catch (const ConfigError& e) {
      throw ConfigError(file->string() + ": " + e.what());
    }
    if (from_file.is_object()) {
      // section by section, key by key (values such as env.options replace
      // the default whole)
      for (const auto& [section, value] : from_file.items()) {
        if (value.is_null()) continue;
        for (const auto& [key, v] : value.items()) tree[section][key] = v;
      }
    }
  }
  ApplyOverrides(tree, overrides);
  TrainConfig config = FromJson(tree);
  CheckMetaTestKeys(from_file, overrides, config.meta_test);
  return config;
}

nlohmann::json TrainConfig::ToJson() const {
  return {
      {"env",
       {{"id", env.id},
        {"tasks", env.tasks},
        {"num_tasks", env.num_tasks},
        {"variations_per_task", env.variations_per_task},
        {"task_states", env.task_states},
        {"options", env.options},
        {"envs_per_task", env.envs_per_task},
        {"task_seed", env.task_seed},
        {"support_variations", env.support_variations},
        {"query_variations", env.query_variations}}},
      {"eval_env", eval_env ? nlohmann::json{{"id", eval_env->id},
                                             {"tasks", eval_env->tasks},
                                             {"num_tasks", eval_env->num_tasks},
                                             {"variations_per_task", eval_env->variations_per_task},
                                             {"task_states", eval_env->task_states},
                                             {"options", eval_env->options},
                                             {"task_seed", eval_env->task_seed},
                                             {"support_variations", eval_env->support_variations},
                                             {"query_variations", eval_env->query_variations}}
                            : nlohmann::json(nullptr)},
      {"meta_test", MetaTestJson(meta_test)},
      {"agent", AgentConfigToJson(agent)},
      {"replay", {{"capacity", replay.capacity}, {"sampling", replay.sampling}}},
      {"experiment",
       {{"seed", experiment.seed},
        {"steps_per_task", experiment.steps_per_task},
        {"warmup_steps", experiment.warmup_steps},
        {"updates_per_step", experiment.updates_per_step},
        {"batch_size", experiment.batch_size},
        {"eval_every", experiment.eval_every},
        {"eval_episodes", experiment.eval_episodes},
        {"eval_terminate_on_success", experiment.eval_terminate_on_success},
        {"num_threads", experiment.num_threads},
        {"checkpoint_every", experiment.checkpoint_every},
        {"keep_checkpoints", experiment.keep_checkpoints},
        {"run_dir", experiment.run_dir},
        {"init_from", experiment.init_from}}},
  };
}

int64_t TrainConfig::TotalBatchSize(int64_t num_tasks) const {
  if (experiment.batch_size > 0) return experiment.batch_size;
  // The off-policy agents' batch_size key: rows per task.
  const nlohmann::json params = agent.params().ToJson();
  if (!params.contains("batch_size") || !params["batch_size"].is_number_integer()) {
    throw ConfigError("agent.algo '" + agent.algo() +
                      "' has no batch_size; set experiment.batch_size");
  }
  return params["batch_size"].get<int64_t>() * num_tasks;
}

// Upper bounds: every count the loops multiply stays far from int64
// overflow (steps x envs x dims), and sizes that could only exhaust memory
// are refused up front instead of killing the process.
constexpr int64_t kMaxSteps = 1000000000000;  // 1e12 env steps per env
constexpr int64_t kMaxEpisodes = 1000000;
constexpr int64_t kMaxTasks = 100000;
constexpr int64_t kMaxVariations = 1000000;
constexpr int64_t kMaxEnvsPerTask = 4096;
constexpr int64_t kMaxReplay = 1000000000;
constexpr int64_t kMaxBatch = 10000000;

// The task counts of an env section (env and eval_env alike).
static void CheckTaskCounts(const EnvSectionConfig& env, const std::string& section) {
  if (env.num_tasks < 0 || env.num_tasks > kMaxTasks) {
    Bad(section + ".num_tasks", "must be in [0, " + std::to_string(kMaxTasks) + "], got " +
                                    std::to_string(env.num_tasks));
  }
  if (env.variations_per_task < 0 || env.variations_per_task > kMaxVariations) {
    Bad(section + ".variations_per_task", "must be in [0, " + std::to_string(kMaxVariations) +
                                              "] (0 = all), got " +
                                              std::to_string(env.variations_per_task));
  }
}

void TrainConfig::Validate() const {
  // env
  if (env.id.empty() == env.tasks.empty()) {
    throw ConfigError(env.id.empty()
                          ? "'env' needs an env id ('env.id: point-nav') or a task list "
                            "('env.tasks: [reach, push]')"
                          : "'env.id' and 'env.tasks' are exclusive; give one of them");
  }
  for (const auto& id : env.tasks) {
    if (id.empty()) Bad("env.tasks", "must not hold an empty id");
  }
  CheckTaskCounts(env, "env");
  if (!env.tasks.empty() && env.num_tasks != 0) {
    Bad("env.num_tasks", "applies to 'env.id' only; with 'env.tasks' each id is one task");
  }
  if (!env.task_states.is_array()) Bad("env.task_states", "must be a list of task states");
  for (const auto& s : env.task_states) {
    if (!s.is_object() || !s.contains("env") || !s.contains("params")) {
      Bad("env.task_states", "entries must be task states {env: ..., params: {...}}, got " +
                                 s.dump());
    }
  }
  if (!env.options.is_object()) Bad("env.options", "must be a mapping of registry options");
  if (env.envs_per_task < 1 || env.envs_per_task > kMaxEnvsPerTask) {
    Bad("env.envs_per_task", "must be in [1, " + std::to_string(kMaxEnvsPerTask) + "], got " +
                                 std::to_string(env.envs_per_task));
  }
  CheckSplitKeys(env, "env");
  if (eval_env) {
    CheckSplitKeys(*eval_env, "eval_env");
    if (eval_env->id.empty() == eval_env->tasks.empty()) {
      Bad("eval_env", "needs an env id or a task list (not both)");
    }
    // the same bounds as env's (unbounded, 2^63-1 variations were allocated until killed)
    CheckTaskCounts(*eval_env, "eval_env");
    if (!eval_env->options.is_object()) Bad("eval_env.options", "must be a mapping");
    if (!eval_env->task_states.is_array()) Bad("eval_env.task_states", "must be a list");
  }
  meta_test.Validate();
  // agent
  ValidateAgentConfig(agent);
  // replay
  if (replay.capacity < 1 || replay.capacity > kMaxReplay) {
    Bad("replay.capacity", "must be in [1, " + std::to_string(kMaxReplay) + "], got " +
                               std::to_string(replay.capacity));
  }
  if (replay.sampling != "uniform" && replay.sampling != "balanced") {
    Bad("replay.sampling", "must be 'uniform' or 'balanced', got '" + replay.sampling + "'");
  }
  if (FindAlgorithm(agent.algo()).family != AlgorithmFamily::kOffPolicy) {
    // keys this algorithm would silently ignore
    const TrainConfig defaults;
    const auto& d = defaults.experiment;
    const char* ignored = nullptr;
    if (replay.capacity != defaults.replay.capacity || replay.sampling != defaults.replay.sampling) {
      ignored = "replay";
    } else if (experiment.warmup_steps != d.warmup_steps) {
      ignored = "experiment.warmup_steps";
    } else if (experiment.updates_per_step != d.updates_per_step) {
      ignored = "experiment.updates_per_step";
    } else if (experiment.batch_size != d.batch_size) {
      ignored = "experiment.batch_size";
    }
    if (ignored != nullptr) {
      Bad(ignored, "applies to off-policy algorithms only; agent.algo '" + agent.algo() +
                       "' is on-policy (its batch is agent.rollout_rounds rounds of every env)");
    }
  }
  // experiment
  const auto& e = experiment;
  if (e.steps_per_task < 1 || e.steps_per_task > kMaxSteps) {
    Bad("experiment.steps_per_task", "must be in [1, " + std::to_string(kMaxSteps) + "], got " +
                                         std::to_string(e.steps_per_task));
  }
  if (e.warmup_steps < 0 || e.warmup_steps > kMaxSteps) {
    Bad("experiment.warmup_steps", "must be in [0, " + std::to_string(kMaxSteps) + "], got " +
                                       std::to_string(e.warmup_steps));
  }
  if (!(std::isfinite(e.updates_per_step) && e.updates_per_step >= 0 &&
        e.updates_per_step <= 1000)) {
    Bad("experiment.updates_per_step",
        "must be in [0, 1000], got " + nlohmann::json(e.updates_per_step).dump());
  }
  if (e.batch_size < 0 || e.batch_size > kMaxBatch) {
    Bad("experiment.batch_size", "must be in [0, " + std::to_string(kMaxBatch) +
                                     "] (0 = agent.batch_size x num_tasks), got " +
                                     std::to_string(e.batch_size));
  }
  if (e.eval_every < 0 || e.eval_every > kMaxSteps) {
    Bad("experiment.eval_every", "must be in [0, " + std::to_string(kMaxSteps) +
                                     "] (0 = only at the end), got " +
                                     std::to_string(e.eval_every));
  }
  if (e.eval_episodes < 1 || e.eval_episodes > kMaxEpisodes) {
    Bad("experiment.eval_episodes", "must be in [1, " + std::to_string(kMaxEpisodes) +
                                        "], got " + std::to_string(e.eval_episodes));
  }
  if (e.num_threads < 1 || e.num_threads > kMaxThreads) {
    Bad("experiment.num_threads", "must be in [1, " + std::to_string(kMaxThreads) + "], got " +
                                      std::to_string(e.num_threads));
  }
  if (e.checkpoint_every < 0 || e.checkpoint_every > kMaxSteps) {
    Bad("experiment.checkpoint_every", "must be in [0, " + std::to_string(kMaxSteps) +
                                           "] (0 = only at the end), got " +
                                           std::to_string(e.checkpoint_every));
  }
  if (e.keep_checkpoints < 0 || e.keep_checkpoints > kMaxEpisodes) {
    Bad("experiment.keep_checkpoints", "must be in [0, " + std::to_string(kMaxEpisodes) +
                                           "] (0 = keep all), got " +
                                           std::to_string(e.keep_checkpoints));
  }
  if (e.run_dir.empty()) Bad("experiment.run_dir", "must not be empty");
}

}  // namespace manyworlds::experiments
