// The configuration of `manyworlds demo` (configs/demo.yaml).
#ifndef APPS_MANYWORLDS_DEMO_CONFIG_H_
#define APPS_MANYWORLDS_DEMO_CONFIG_H_

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/registry.h"

namespace manyworlds::cli {

struct DemoConfig {
  int episodes = 10;          // episodes per env, >= 1
  uint64_t seed = 0;          // env seed (and the policy's, mixed)
  uint64_t task_seed = 0;     // task seed
  std::string policy = "random";
  std::vector<std::string> envs;  // env ids; empty: every registered env
  std::string out_dir = "runs/demo";

  // Defaults, then the file's keys (if any), then the dotted overrides;
  // unknown keys and ill-typed values are ConfigErrors.
  static DemoConfig Load(const std::optional<std::filesystem::path>& file,
                         const std::vector<std::string>& overrides);
  // Throws ConfigError for bad values or unknown env ids, and replaces an
  // empty env list with every registered id.
  void Resolve(const Registry& registry);
  nlohmann::json ToJson() const;
};

}  // namespace manyworlds::cli

#endif  // APPS_MANYWORLDS_DEMO_CONFIG_H_
