// Any text as a task state of a MuJoCo env: the manipulation tasks, the
// benchmarks (mt10, ml10, mt1, ml1), half-cheetah-vel and -dir, the box
// worlds (box-world-simple and -complex, whose state builds a model), and the
// dm_control-style envs (dmc-*, and hipbmdp-*, whose state picks a compiled
// model). The
// first byte picks the env: 0 the one the state's "env" field names (so that the
// seeds stay valid when the registry grows), n > 0 the (n-1)th in registry
// order (states of one env given to another). TaskState::Parse and
// Env::SetTaskState accept it or throw an Error; an accepted state
//  - reads back with GetTaskState, and that state, dumped and parsed, is
//    accepted again and reads back the same;
//  - resets and steps (5 steps of zero actions) with finite observations and
//    rewards, or an Error.
// The envs are made once (a model per input would cost milliseconds). The
// box worlds are made with max_boxes = 64 (the most a world may hold), so
// that every valid world fits one; their task states build a new model
// whenever the world's structure changes.
//
// MANYWORLDS_FUZZ_ENVS=PREFIX keeps only the envs whose id starts with it
// (e.g. box-world, to spend a run on one suite; n > 0 then counts among
// those).
//
// MANYWORLDS_FUZZ_WRITE_SEEDS=DIR writes one valid task state per env into
// DIR (as tests/fuzz/corpus/task_state_mujoco/ holds them) and exits; run it
// again when a task's ranges change (a seed that is refused still parses,
// but no longer reaches reset and step). Each box world also gets a crowded
// seed (<id>-crowded.txt: 24 boxes of every shape).
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

#include <nlohmann/json.hpp>

#include "manyworlds/boxworld/boxworld.h"
#include "manyworlds/boxworld/world.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/core/task_state.h"
#include "manyworlds/dmc/dmc.h"
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
    manyworlds::RegisterBoxWorldSuite(registry);
    manyworlds::RegisterDmcSuite(registry);  // last: the n > 0 picks of older inputs stay
    const char* only = std::getenv("MANYWORLDS_FUZZ_ENVS");
    for (const std::string& id : registry.Ids()) {
      if (only != nullptr && !id.starts_with(only)) continue;
      nlohmann::json options = nlohmann::json::object();
      if (id.starts_with("box-world")) options["max_boxes"] = 64;
      ids.push_back(id);
      all.push_back(registry.Make(id, options));
    }
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

void WriteSeed(const std::string& name, const manyworlds::TaskState& state) {
  if (state.Dump().size() >= 4096) {
    std::fprintf(stderr, "%s: over the 4096 bytes of scripts/fuzz.sh's -max_len\n", name.c_str());
    std::exit(1);
  }
  std::ofstream out(name, std::ios::binary);
  out << '\0' << state.Dump();  // the env its "env" field names
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", name.c_str());
    std::exit(1);
  }
}

// To 3 decimals (1 mm), so that the crowded seed stays within the 4096
// bytes scripts/fuzz.sh gives an input (-max_len).
void RoundNumbers(nlohmann::json& json) {
  if (json.is_number_float()) json = std::round(json.get<double>() * 1000) / 1000;
  if (!json.is_structured()) return;  // a scalar iterates over itself
  for (nlohmann::json& item : json) RoundNumbers(item);
}

void WriteSeeds(const std::string& dir) {
  Envs& envs = AllEnvs();
  for (size_t i = 0; i < envs.all.size(); ++i) {
    manyworlds::Env& env = *envs.all[i];
    env.SeedTask(1);
    WriteSeed(dir + "/" + envs.ids[i] + ".txt", env.SampleTaskState());
    if (!envs.ids[i].starts_with("box-world")) continue;
    // and a crowded world: 24 boxes of every shape on a 10 m floor
    manyworlds::boxworld::WorldDistribution crowded;
    crowded.floor_size = {10.0, 10.0};
    crowded.num_boxes = {24, 24};
    crowded.box_shapes = {manyworlds::boxworld::Shape::kBox,
                          manyworlds::boxworld::Shape::kCylinder,
                          manyworlds::boxworld::Shape::kSphere};
    crowded.box_size = {0.05, 0.5};
    crowded.random_colors = true;
    crowded.success_radius_ratio = 0.05;  // 0.5 m: room for the target
    crowded.min_target_distance_ratio = 0.05;
    nlohmann::json world = manyworlds::boxworld::ToJson(GenerateWorld(crowded, 1));
    RoundNumbers(world);
    manyworlds::boxworld::WorldFromJson(world);  // still valid
    WriteSeed(dir + "/" + envs.ids[i] + "-crowded.txt", manyworlds::TaskState{envs.ids[i], world});
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
  if (size == 0 || envs.all.empty()) return 0;
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
