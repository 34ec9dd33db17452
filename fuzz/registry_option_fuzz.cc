// Any text as `--option key=value` lines for a classic env (the first byte picks the env):
// Registry::Make accepts the options or throws a ConfigError of one line, and an env made
// with accepted options resets and steps with finite observations and rewards. Option
// values arrive as strings, as from the command line and YAML configs, so the registry's own
// parsing of numbers, booleans and nested text is what this explores.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/classic/classic.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"

namespace {

const manyworlds::Registry& Classic() {
  static const manyworlds::Registry registry = [] {
    manyworlds::Registry r;
    manyworlds::RegisterClassicSuite(r);
    return r;
  }();
  return registry;
}

void RequireFinite(std::span<const float> values) {
  for (const float v : values) {
    if (!std::isfinite(v)) std::abort();  // an accepted option made a non-finite observation
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const manyworlds::Registry& registry = Classic();
  const std::vector<std::string> ids = registry.Ids();
  const std::string& id = ids[data[0] % ids.size()];
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  nlohmann::json options = nlohmann::json::object();
  for (size_t start = 0; start <= text.size();) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(start, end - start);
    const size_t equals = line.find('=');
    if (equals != std::string_view::npos) {
      options[std::string(line.substr(0, equals))] = std::string(line.substr(equals + 1));
    }
    start = end + 1;
  }
  std::unique_ptr<manyworlds::Env> env;
  try {
    env = registry.Make(id, options);
  } catch (const manyworlds::ConfigError& e) {
    // a refusal is one line of bounded length, whatever the input
    const std::string_view what = e.what();
    if (what.find('\n') != std::string_view::npos || what.size() > 2000) std::abort();
    return 0;
  }
  const manyworlds::Space& action = env->spec().action_space;
  std::vector<float> a(action.flat_size(), 0.0f);
  try {
    env->SeedTask(1);
    env->ResetTaskState();
    const manyworlds::Observation obs = env->Reset();
    RequireFinite(obs.env_obs);
    RequireFinite(obs.task_obs);
    for (int t = 0; t < 5; ++t) {
      const manyworlds::StepResult r = env->Step(a);
      RequireFinite(r.obs.env_obs);
      if (!std::isfinite(r.reward)) std::abort();
      if (r.terminated || r.truncated) env->Reset();
    }
  } catch (const manyworlds::Error&) {
    // e.g. a Box action of zeros outside its space: refused, as it should be
  }
  return 0;
}
