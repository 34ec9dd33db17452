#include "apps/manyworlds/demo_config.h"

#include "apps/manyworlds/cli_util.h"
#include "manyworlds/config/override.h"
#include "manyworlds/config/reader.h"
#include "manyworlds/config/yaml.h"
#include "manyworlds/core/error.h"

namespace manyworlds::cli {

DemoConfig DemoConfig::Load(const std::optional<std::filesystem::path>& file,
                            const std::vector<std::string>& overrides) {
  // start from every default so that `key=value` works for keys the file omits
  nlohmann::json json = DemoConfig{}.ToJson();
  if (file) {
    const nlohmann::json loaded = LoadYamlFile(*file);
    if (!loaded.is_null() && !loaded.is_object()) {
      throw ConfigError(file->string() + ": expected a map of keys to values, got a " +
                        loaded.type_name());
    }
    if (loaded.is_object()) {
      for (const auto& [key, value] : loaded.items()) json[key] = value;
    }
  }
  ApplyOverrides(json, overrides);
  DemoConfig config;
  ConfigReader reader(json);
  reader.Read("episodes", config.episodes);
  reader.Read("seed", config.seed);
  reader.Read("task_seed", config.task_seed);
  reader.Read("policy", config.policy);
  reader.Read("envs", config.envs);
  reader.Read("out_dir", config.out_dir);
  reader.Finish();
  return config;
}

void DemoConfig::Resolve(const Registry& registry) {
  if (episodes < 1) {
    throw ConfigError("config key 'episodes' must be >= 1, got " + std::to_string(episodes));
  }
  if (out_dir.empty()) throw ConfigError("config key 'out_dir' must not be empty");
  CheckPolicyName(policy);
  for (const auto& id : envs) registry.Find(id);  // unknown ids throw, with suggestions
  if (envs.empty()) envs = registry.Ids();
}

nlohmann::json DemoConfig::ToJson() const {
  return {{"episodes", episodes}, {"seed", seed},   {"task_seed", task_seed},
          {"policy", policy},     {"envs", envs},   {"out_dir", out_dir}};
}

}  // namespace manyworlds::cli
