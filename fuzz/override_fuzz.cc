// Any text as a `key=value` override of a small config: applied, or a
// ConfigError, never anything else.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "manyworlds/config/override.h"
#include "manyworlds/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  nlohmann::json config = {
      {"env", {{"id", "point-nav"}, {"options", {{"horizon", 50}}}, {"num_tasks", 3}}},
      {"agent", {{"algo", "sac"}, {"hidden_dim", 64}}},
      {"experiment", {{"seed", 1}, {"steps_per_task", 1000}}},
      {"list", {1, 2, 3}}};
  try {
    manyworlds::ApplyOverride(config, std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const manyworlds::ConfigError&) {
  }
  return 0;
}
