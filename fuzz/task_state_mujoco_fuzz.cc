// Any text as a task state of a MuJoCo env (the first byte picks the env, in
// registry order: the manipulation tasks, the benchmarks mt10, ml10, mt1,
// ml1, then half-cheetah-vel and half-cheetah-dir). TaskState::Parse and
// Env::SetTaskState accept it or throw an Error; an accepted state
//  - reads back with GetTaskState, and that state, dumped and parsed, is
//    accepted again and reads back the same;
//  - resets and steps (5 steps of zero actions) with finite observations and
//    rewards, or an Error.
// The envs are made once (a model per input would cost milliseconds).
//
// MANYWORLDS_FUZZ_WRITE_SEEDS=DIR writes one valid task state per env into
// DIR (as tests/fuzz/corpus/task_state_mujoco/ holds them) and exits.
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
    const std::string name = dir + "/" + std::to_string(i) + "_" + envs.ids[i] + ".txt";
    std::ofstream out(name, std::ios::binary);
    out << static_cast<char>(i) << env.SampleTaskState().Dump();
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
  manyworlds::Env& env = *envs.all[data[0] % envs.all.size()];
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    env.SetTaskState(manyworlds::TaskState::Parse(text));
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
