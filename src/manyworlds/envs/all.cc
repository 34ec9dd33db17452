#include "manyworlds/envs/all.h"

#include <algorithm>

#include "manyworlds/classic/classic.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/wrapper.h"
#ifdef MANYWORLDS_HAS_SIM
#include "manyworlds/sim/pixel_observation.h"
#include "manyworlds/sim/scene_source.h"
#endif
#ifdef MANYWORLDS_HAS_BOXWORLD
#include "manyworlds/boxworld/boxworld.h"
#endif
#ifdef MANYWORLDS_HAS_DMC
#include "manyworlds/dmc/dmc.h"
#endif
#ifdef MANYWORLDS_HAS_LOCOMOTION
#include "manyworlds/locomotion/locomotion.h"
#endif
#ifdef MANYWORLDS_HAS_MANIPULATION
#include "manyworlds/manipulation/manipulation.h"
#endif

namespace manyworlds {

const Registry& DefaultRegistry() {
  // a function-local static is initialised exactly once, even under races
  static const Registry registry = [] {
    Registry r;
    RegisterClassicSuite(r);
#ifdef MANYWORLDS_HAS_MANIPULATION
    RegisterManipulationSuite(r);
#endif
#ifdef MANYWORLDS_HAS_LOCOMOTION
    RegisterLocomotionSuite(r);
#endif
#ifdef MANYWORLDS_HAS_DMC
    RegisterDmcSuite(r);
#endif
#ifdef MANYWORLDS_HAS_BOXWORLD
    RegisterBoxWorldSuite(r);
#endif
#ifdef MANYWORLDS_HAS_SIM
    r.SetPixelWrapper(sim::MakePixelObservation);
#endif
    return r;
  }();
  return registry;
}

std::unique_ptr<Env> Make(std::string_view id, const nlohmann::json& options) {
  return DefaultRegistry().Make(id, options);
}

namespace {

// What the scripted-policy, render and export errors allow, in one place.
constexpr char kScriptedEnvs[] = "the manipulation tasks and benchmarks and box-world-*";
#ifdef MANYWORLDS_HAS_SIM
constexpr char kMujocoEnvs[] =
    "the MuJoCo envs (manipulation tasks and benchmarks, box-world-*, half-cheetah-*, dmc-*, "
    "hipbmdp-*)";
#else
constexpr char kMujocoEnvs[] = "the MuJoCo envs, which this build lacks (MuJoCo was not found)";
#endif

// `use` is "rendering" or "export-xml".
ConfigError NoSceneError(const Env& env, const std::string& use) {
  return ConfigError("env '" + env.id() + "' has no MuJoCo scene; " + use + " works for " +
                     kMujocoEnvs);
}

#ifdef MANYWORLDS_HAS_SIM
// The env's MuJoCo scene capability, found behind wrappers.
const sim::SceneSource& SceneSourceOf(const Env& env, const std::string& use) {
  const auto* source = FindThroughWrappers<sim::SceneSource>(env);
  if (source == nullptr) throw NoSceneError(env, use);
  return *source;
}
#endif

}  // namespace

std::unique_ptr<Policy> MakeScriptedPolicy(const Env& env) {
  if (const auto* source = FindThroughWrappers<ScriptedPolicySource>(env)) {
    return source->CreateScriptedPolicy();
  }
  throw ConfigError("no scripted policy for env '" + env.id() + "': scripted policies exist for " +
                    kScriptedEnvs);
}

const std::vector<std::string>& PolicyNames() {
  static const std::vector<std::string> names = {"random", "scripted"};
  return names;
}

void CheckPolicyName(std::string_view name) {
  const auto& names = PolicyNames();
  if (std::find(names.begin(), names.end(), name) != names.end()) return;
  std::string allowed;
  for (const auto& n : names) allowed += (allowed.empty() ? "" : ", ") + n;
  throw ConfigError("unknown policy '" + std::string(name) + "'" + SuggestNearest(name, names) +
                    "; allowed: " + allowed);
}

std::unique_ptr<Policy> MakePolicy(std::string_view name, const Env& env, uint64_t seed) {
  CheckPolicyName(name);
  if (name == "scripted") return MakeScriptedPolicy(env);
  return std::make_unique<RandomPolicy>(env.spec().action_space, seed);
}

#ifdef MANYWORLDS_HAS_SIM

void CheckMujocoEnv(const Env& env, const std::string& use) { SceneSourceOf(env, use); }

void SaveTaskXml(const Env& env, const std::string& path) {
  SceneSourceOf(env, "export-xml").SaveSceneXml(path);
}

MujocoScene ActiveMujocoScene(const Env& env) {
  const sim::SceneSource& source = SceneSourceOf(env, "rendering");
  const sim::Scene scene = source.ActiveScene();
  if (scene.model == nullptr) {
    throw ConfigError("env '" + env.id() + "' has no task yet, hence no scene; call "
                      "ResetTaskState or SetTaskState first");
  }
  return {scene.model, scene.data, source.default_camera()};
}

#else  // !MANYWORLDS_HAS_SIM: no env has a scene

void CheckMujocoEnv(const Env& env, const std::string& use) { throw NoSceneError(env, use); }
void SaveTaskXml(const Env& env, const std::string&) { throw NoSceneError(env, "export-xml"); }
MujocoScene ActiveMujocoScene(const Env& env) { throw NoSceneError(env, "rendering"); }

#endif  // MANYWORLDS_HAS_SIM

std::string PixelObservationNote(const Env& env) {
  const Space& pixels = env.spec().pixel_space;
  if (pixels.flat_size() == 0) return "";
  std::string shape;
  for (int64_t d : pixels.shape()) shape += (shape.empty() ? "" : "x") + std::to_string(d);
  std::string note = "pixel observations " + shape;
#ifdef MANYWORLDS_HAS_SIM
  if (const auto* wrapper = FindThroughWrappers<sim::PixelObservation>(env)) {
    note += " from camera '" + wrapper->camera() + "'";
  }
#endif
#ifdef MANYWORLDS_HAS_RENDER
  note += ", rendered with " + sim::RenderBackendName();
#endif
  return note;
}

}  // namespace manyworlds
