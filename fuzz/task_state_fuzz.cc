// Any text as a task state of a classic env (the first byte picks the env):
// TaskState::Parse and Env::SetTaskState accept it or throw an Error, and an
// accepted state runs (reset and a few steps with actions of
// zeros) without anything else going wrong.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "manyworlds/classic/classic.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/core/task_state.h"

namespace {

struct Envs {
  std::vector<std::unique_ptr<manyworlds::Env>> all;
  Envs() {
    manyworlds::Registry registry;
    manyworlds::RegisterClassicSuite(registry);
    for (const std::string& id : registry.Ids()) all.push_back(registry.Make(id, {}));
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Envs envs;
  if (size == 0) return 0;
  manyworlds::Env& env = *envs.all[data[0] % envs.all.size()];
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    env.SetTaskState(manyworlds::TaskState::Parse(text));
  } catch (const manyworlds::Error&) {
    return 0;
  }
  const manyworlds::Space& action = env.spec().action_space;
  std::vector<float> a(action.flat_size(), 0.0f);
  try {
    env.Reset();
    for (int t = 0; t < 5; ++t) {
      const manyworlds::StepResult r = env.Step(a);
      if (r.terminated || r.truncated) env.Reset();
    }
  } catch (const manyworlds::Error&) {
    // e.g. a Box action of zeros outside its space: refused, as it should be
  }
  return 0;
}
