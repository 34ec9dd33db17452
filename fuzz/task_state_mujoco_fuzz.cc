// Any text as a task state of a MuJoCo env: the manipulation tasks, the
// benchmarks (mt10, ml10, mt1, ml1) and half-cheetah-vel and -dir. The first
// byte picks the env: 0 the one the state's "env" field names (so that the
// seeds stay valid when the registry grows), n > 0 the (n-1)th in registry
// order (states of one env given to another). TaskState::Parse and
// Env::SetTaskState accept it or throw an Error; an accepted state
//  - reads back with GetTaskState, and that state, dumped and parsed, is
//    accepted again and reads back the same;
//  - resets and steps (5 steps of zero actions) with finite observations and
//    rewards, or an Error.
// The envs are made once (a model per input would cost milliseconds).
//
// MANYWORLDS_FUZZ_WRITE_SEEDS=DIR writes one valid task state per env into
// DIR (as tests/fuzz/corpus/task_state_mujoco/ holds them) and exits; run it
// again when a task's ranges change (a seed that is refused still parses,
// but no longer reaches reset and step).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/core/task_state.h"
#include "manyworlds/locomotion/locomotion.h"
#include "manyworlds/manipulation/manipulation.h"

namespace {

struct Envs {
  std::vector<std::string> ids;
  std::vector<std::unique_ptr<manyworlds::Env>> all;
  Envs() {
    manyworlds::Registry registry;
    manyworlds::RegisterManipulationSuite(registry);
    manyworlds::RegisterLocomotionSuite(registry);
    ids = registry.Ids();
    for (const std::string& id : ids) all.push_back(registry.Make(id, {}));
  }
};

Envs& AllEnvs() {
  static Envs envs;
  return envs;
}

bool Finite(std::span<const float> values) {
  for (float v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

void WriteSeeds(const std::string& dir) {
  Envs& envs = AllEnvs();
  for (size_t i = 0; i < envs.all.size(); ++i) {
    manyworlds::Env& env = *envs.all[i];
    env.SeedTask(1);
    const std::string name = dir + "/" + envs.ids[i] + ".txt";
    std::ofstream out(name, std::ios::binary);
    out << '\0' << env.SampleTaskState().Dump();  // the env its "env" field names
    if (!out) {
      std::fprintf(stderr, "cannot write %s\n", name.c_str());
      std::exit(1);
    }
  }
  std::exit(0);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MANYWORLDS_FUZZ_WRITE_SEEDS")) WriteSeeds(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Envs& envs = AllEnvs();
  if (size == 0) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  manyworlds::TaskState state;
  try {
    state = manyworlds::TaskState::Parse(text);
  } catch (const manyworlds::Error&) {
    return 0;
  }
  size_t index = data[0] == 0 ? envs.ids.size() : (data[0] - 1u) % envs.all.size();
  for (size_t i = 0; data[0] == 0 && i < envs.ids.size(); ++i) {
    if (envs.ids[i] == state.env) index = i;
  }
  if (index >= envs.all.size()) return 0;  // names no env
  manyworlds::Env& env = *envs.all[index];
  try {
    env.SetTaskState(state);
  } catch (const manyworlds::Error&) {
    return 0;
  }
  // what was accepted reads back, and what reads back is accepted as is
  const manyworlds::TaskState got = env.GetTaskState();
  env.SetTaskState(manyworlds::TaskState::Parse(got.Dump()));
  if (!(env.GetTaskState() == got)) std::abort();

  const manyworlds::Space& action = env.spec().action_space;
  std::vector<float> a(action.flat_size(), 0.0f);
  try {
    manyworlds::Observation obs = env.Reset();
    if (!Finite(obs.env_obs) || !Finite(obs.task_obs)) std::abort();
    for (int t = 0; t < 5; ++t) {
      const manyworlds::StepResult r = env.Step(a);
      if (!Finite(r.obs.env_obs) || !Finite(r.obs.task_obs) || !std::isfinite(r.reward)) {
        std::abort();
      }
      if (r.terminated || r.truncated) env.Reset();
    }
  } catch (const manyworlds::Error&) {
    // e.g. a simulation warning with throw_on_sim_warning: refused, as it should be
  }
  return 0;
}
