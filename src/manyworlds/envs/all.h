// The default registry with every suite manyworlds ships, and the Gym-style
// entry point:
//
//   std::unique_ptr<Env> env = manyworlds::Make("cartpole");
//   std::unique_ptr<Env> bandit = manyworlds::Make("bandit", {{"n_arms", 5}});
#ifndef MANYWORLDS_ENVS_ALL_H_
#define MANYWORLDS_ENVS_ALL_H_

#include <memory>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "manyworlds/core/env.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/core/registry.h"

// MuJoCo's model and data types, declared here so that this header does not
// need MuJoCo's (the build may lack it).
struct mjModel_;
struct mjData_;

namespace manyworlds {

// Built on first use (thread-safe) and never modified afterwards, so it may
// be read from any thread.
const Registry& DefaultRegistry();

// DefaultRegistry().Make(id, options). Throws ConfigError for an unknown id
// (suggesting the nearest ones) or a bad option.
std::unique_ptr<Env> Make(std::string_view id, const nlohmann::json& options = {});

// The scripted (expert) policy of an env that has one (ScriptedPolicySource:
// the manipulation tasks and benchmarks and the box world), also behind
// wrappers. `env` must outlive it. Throws ConfigError for other envs.
std::unique_ptr<Policy> MakeScriptedPolicy(const Env& env);

// The env policies offered by name (the CLI's --policy, eval's PolicyActor):
// "random" (RandomPolicy over the env's action space, from `seed`) and
// "scripted" (MakeScriptedPolicy). CheckPolicyName and MakePolicy throw
// ConfigError for an unknown name, with the nearest one and the list.
const std::vector<std::string>& PolicyNames();
void CheckPolicyName(std::string_view name);
std::unique_ptr<Policy> MakePolicy(std::string_view name, const Env& env, uint64_t seed);

// Writes the complete MJCF of the current task of a MuJoCo env (one that is
// a sim::SceneSource: a manipulation task or benchmark, the box world, the
// half-cheetah; also behind wrappers) to `path`. Throws ConfigError for other
// envs, EpisodeStateError before a benchmark or box world has a task.
void SaveTaskXml(const Env& env, const std::string& path);

// The MuJoCo model and data that simulate the current task of a MuJoCo env
// (as for SaveTaskXml), for rendering, and the camera to render it from
// unless told otherwise.
// Both belong to the env: valid until its next SetTaskState, and the data
// changes with every step. Throws ConfigError for other envs and before a
// benchmark or box world has a task.
struct MujocoScene {
  const mjModel_* model = nullptr;
  const mjData_* data = nullptr;
  std::string_view default_camera = "front";
};
MujocoScene ActiveMujocoScene(const Env& env);

// Throws ActiveMujocoScene's ConfigError, saying what `use` ("rendering")
// works for, unless `env` is a MuJoCo env; a benchmark or box world passes
// before it has a task too.
void CheckMujocoEnv(const Env& env, const std::string& use);

// "pixel observations 9x84x84 from camera 'fixed', rendered with OSMesa (Mesa llvmpipe)" for
// an env made with obs=pixels (what logs say about the frames), "" for other envs.
std::string PixelObservationNote(const Env& env);

}  // namespace manyworlds

#endif  // MANYWORLDS_ENVS_ALL_H_
