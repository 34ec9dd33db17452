#include "manyworlds/envs/all.h"

#include "manyworlds/classic/classic.h"
#include "manyworlds/core/error.h"
#ifdef MANYWORLDS_HAS_BOXWORLD
#include "manyworlds/boxworld/boxworld.h"
#include "manyworlds/boxworld/world_model.h"
#include "manyworlds/core/atomic_file.h"
#endif
#ifdef MANYWORLDS_HAS_LOCOMOTION
#include "manyworlds/locomotion/locomotion.h"
#endif
#ifdef MANYWORLDS_HAS_MANIPULATION
#include "manyworlds/manipulation/benchmark.h"
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
#ifdef MANYWORLDS_HAS_BOXWORLD
    RegisterBoxWorldSuite(r);
#endif
    return r;
  }();
  return registry;
}

std::unique_ptr<Env> Make(std::string_view id, const nlohmann::json& options) {
  return DefaultRegistry().Make(id, options);
}

std::unique_ptr<Policy> MakeScriptedPolicy(const Env& env) {
#ifdef MANYWORLDS_HAS_BOXWORLD
  if (std::unique_ptr<Policy> policy = boxworld::MakeScriptedPolicy(env)) return policy;
#endif
#ifdef MANYWORLDS_HAS_MANIPULATION
  return manipulation::MakeScriptedPolicyFor(env);
#else
  throw ConfigError("no scripted policy for env '" + env.id() +
                    "': this build has no manipulation suite (MuJoCo was not found)");
#endif
}

void SaveTaskXml(const Env& env, const std::string& path) {
#ifdef MANYWORLDS_HAS_BOXWORLD
  if (const boxworld::BoxWorldEnv* box = boxworld::FindBoxWorld(env); box && box->has_task()) {
    AtomicWriteFile(path, boxworld::WorldMjcf(box->world()).ToXml());
    return;
  }
#endif
#ifdef MANYWORLDS_HAS_MANIPULATION
  if (const manipulation::SawyerTask* task = manipulation::ActiveSawyerTask(env)) {
    task->SaveVariationXml(path);
    return;
  }
#else
  (void)path;
#endif
  throw ConfigError("env '" + env.id() +
                    "' has no MuJoCo model to export; export-xml works for the manipulation "
                    "tasks, benchmarks and the box world");
}

MujocoScene ActiveMujocoScene(const Env& env) {
#ifdef MANYWORLDS_HAS_BOXWORLD
  if (const boxworld::BoxWorldEnv* box = boxworld::FindBoxWorld(env); box && box->has_task()) {
    return {box->model(), box->data()};
  }
#endif
#ifdef MANYWORLDS_HAS_MANIPULATION
  if (const manipulation::SawyerTask* task = manipulation::ActiveSawyerTask(env)) {
    return {task->model(), task->data()};
  }
#endif
  throw ConfigError("env '" + env.id() +
                    "' has no MuJoCo scene; rendering works for the manipulation tasks, benchmarks "
                    "and the box world");
}

}  // namespace manyworlds
