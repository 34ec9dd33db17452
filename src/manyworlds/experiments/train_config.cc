#include "manyworlds/experiments/train_config.h"

#include <cmath>
#include <string>

#include "manyworlds/config/override.h"
#include "manyworlds/config/reader.h"
#include "manyworlds/config/yaml.h"
#include "manyworlds/core/error.h"

namespace manyworlds::experiments {
namespace {

void ReadAgent(ConfigReader r, agents::SacConfig& c) {
  r.Read("hidden_dim", c.hidden_dim);
  r.Read("num_layers", c.num_layers);
  r.Read("actor_lr", c.actor_lr);
  r.Read("critic_lr", c.critic_lr);
  r.Read("alpha_lr", c.alpha_lr);
  r.Read("adam_beta1", c.adam_beta1);
  r.Read("adam_beta2", c.adam_beta2);
  r.Read("discount", c.discount);
  r.Read("tau", c.tau);
  r.Read("init_temperature", c.init_temperature);
  r.Read("batch_size", c.batch_size);
  if (r.Has("target_entropy")) {
    nlohmann::json value;
    r.Read("target_entropy", value);
    if (value.is_null()) {
      c.target_entropy.reset();
    } else if (value.is_number()) {
      c.target_entropy = value.get<double>();
    } else {
      throw ConfigError("'" + r.FullKey("target_entropy") +
                        "' must be a number or null (= -action_dim), got " + value.dump());
    }
  }
  r.Read("disentangled_alpha", c.disentangled_alpha);
  r.Read("log_std_min", c.log_std_min);
  r.Read("log_std_max", c.log_std_max);
  r.Read("actor_update_freq", c.actor_update_freq);
  r.Read("critic_target_update_freq", c.critic_target_update_freq);
  r.Read("max_critic_loss", c.max_critic_loss);
  r.Read("seed", c.seed);
  r.Read("architecture", c.architecture);
  r.Read("task_embedding_dim", c.task_embedding_dim);
  r.Read("num_experts", c.num_experts);
  r.Read("encoder_dim", c.encoder_dim);
  r.Read("pcgrad", c.pcgrad);
  r.Read("update_shards", c.update_shards);
  r.Read("update_threads", c.update_threads);
  r.Finish();
}

nlohmann::json AgentToJson(const agents::SacConfig& c) {
  nlohmann::json j = {
      {"hidden_dim", c.hidden_dim},
      {"num_layers", c.num_layers},
      {"actor_lr", c.actor_lr},
      {"critic_lr", c.critic_lr},
      {"alpha_lr", c.alpha_lr},
      {"adam_beta1", c.adam_beta1},
      {"adam_beta2", c.adam_beta2},
      {"discount", c.discount},
      {"tau", c.tau},
      {"init_temperature", c.init_temperature},
      {"batch_size", c.batch_size},
      {"target_entropy",
       c.target_entropy ? nlohmann::json(*c.target_entropy) : nlohmann::json(nullptr)},
      {"disentangled_alpha", c.disentangled_alpha},
      {"log_std_min", c.log_std_min},
      {"log_std_max", c.log_std_max},
      {"actor_update_freq", c.actor_update_freq},
      {"critic_target_update_freq", c.critic_target_update_freq},
      {"max_critic_loss", c.max_critic_loss},
      {"seed", c.seed},
      {"architecture", c.architecture},
      {"task_embedding_dim", c.task_embedding_dim},
      {"num_experts", c.num_experts},
      {"encoder_dim", c.encoder_dim},
      {"pcgrad", c.pcgrad},
      {"update_shards", c.update_shards},
      {"update_threads", c.update_threads},
  };
  return j;
}

// The full default tree, so that dotted overrides can name any key.
nlohmann::json DefaultTree() { return TrainConfig{}.ToJson(); }

[[noreturn]] void Bad(const std::string& key, const std::string& what) {
  throw ConfigError("'" + key + "' " + what);
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
    r.Finish();
    if (c.env.task_states.is_null()) c.env.task_states = nlohmann::json::array();
    if (c.env.options.is_null()) c.env.options = nlohmann::json::object();
  }
  ReadAgent(root.Section("agent"), c.agent);
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
    r.Read("num_threads", e.num_threads);
    r.Read("checkpoint_every", e.checkpoint_every);
    r.Read("keep_checkpoints", e.keep_checkpoints);
    r.Read("run_dir", e.run_dir);
    r.Finish();
  }
  root.Finish();
  return c;
}

TrainConfig TrainConfig::Load(const std::optional<std::filesystem::path>& file,
                              const std::vector<std::string>& overrides) {
  nlohmann::json tree = DefaultTree();
  if (file) {
    nlohmann::json from_file = LoadYamlFile(*file);
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
  return FromJson(tree);
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
        {"task_seed", env.task_seed}}},
      {"agent", AgentToJson(agent)},
      {"replay", {{"capacity", replay.capacity}, {"sampling", replay.sampling}}},
      {"experiment",
       {{"seed", experiment.seed},
        {"steps_per_task", experiment.steps_per_task},
        {"warmup_steps", experiment.warmup_steps},
        {"updates_per_step", experiment.updates_per_step},
        {"batch_size", experiment.batch_size},
        {"eval_every", experiment.eval_every},
        {"eval_episodes", experiment.eval_episodes},
        {"num_threads", experiment.num_threads},
        {"checkpoint_every", experiment.checkpoint_every},
        {"keep_checkpoints", experiment.keep_checkpoints},
        {"run_dir", experiment.run_dir}}},
  };
}

agents::ReplaySampling TrainConfig::sampling() const {
  try {
    return agents::ParseReplaySampling(replay.sampling);
  } catch (const ConfigError&) {
    Bad("replay.sampling", "must be 'uniform' or 'balanced', got '" + replay.sampling + "'");
  }
}

int64_t TrainConfig::TotalBatchSize(int64_t num_tasks) const {
  return experiment.batch_size > 0 ? experiment.batch_size : agent.batch_size * num_tasks;
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
  if (env.num_tasks < 0) Bad("env.num_tasks", "must be >= 0, got " + std::to_string(env.num_tasks));
  if (!env.tasks.empty() && env.num_tasks != 0) {
    Bad("env.num_tasks", "applies to 'env.id' only; with 'env.tasks' each id is one task");
  }
  if (env.variations_per_task < 0) {
    Bad("env.variations_per_task",
        "must be >= 0 (0 = all), got " + std::to_string(env.variations_per_task));
  }
  if (!env.task_states.is_array()) Bad("env.task_states", "must be a list of task states");
  for (const auto& s : env.task_states) {
    if (!s.is_object() || !s.contains("env") || !s.contains("params")) {
      Bad("env.task_states", "entries must be task states {env: ..., params: {...}}, got " +
                                 s.dump());
    }
  }
  if (!env.options.is_object()) Bad("env.options", "must be a mapping of registry options");
  if (env.envs_per_task < 1) {
    Bad("env.envs_per_task", "must be >= 1, got " + std::to_string(env.envs_per_task));
  }
  // agent
  agent.Validate();
  // replay
  if (replay.capacity < 1) Bad("replay.capacity", "must be >= 1, got " + std::to_string(replay.capacity));
  sampling();
  // experiment
  const auto& e = experiment;
  if (e.steps_per_task < 1) {
    Bad("experiment.steps_per_task", "must be >= 1, got " + std::to_string(e.steps_per_task));
  }
  if (e.warmup_steps < 0) {
    Bad("experiment.warmup_steps", "must be >= 0, got " + std::to_string(e.warmup_steps));
  }
  if (!(std::isfinite(e.updates_per_step) && e.updates_per_step >= 0 &&
        e.updates_per_step <= 1000)) {
    Bad("experiment.updates_per_step",
        "must be in [0, 1000], got " + nlohmann::json(e.updates_per_step).dump());
  }
  if (e.batch_size < 0) {
    Bad("experiment.batch_size",
        "must be >= 0 (0 = agent.batch_size x num_tasks), got " + std::to_string(e.batch_size));
  }
  if (e.eval_every < 0) {
    Bad("experiment.eval_every", "must be >= 0 (0 = only at the end), got " +
                                     std::to_string(e.eval_every));
  }
  if (e.eval_episodes < 1) {
    Bad("experiment.eval_episodes", "must be >= 1, got " + std::to_string(e.eval_episodes));
  }
  if (e.num_threads < 1 || e.num_threads > 256) {
    Bad("experiment.num_threads", "must be in [1, 256], got " + std::to_string(e.num_threads));
  }
  if (e.checkpoint_every < 0) {
    Bad("experiment.checkpoint_every",
        "must be >= 0 (0 = only at the end), got " + std::to_string(e.checkpoint_every));
  }
  if (e.keep_checkpoints < 0) {
    Bad("experiment.keep_checkpoints",
        "must be >= 0 (0 = keep all), got " + std::to_string(e.keep_checkpoints));
  }
  if (e.run_dir.empty()) Bad("experiment.run_dir", "must not be empty");
}

}  // namespace manyworlds::experiments
