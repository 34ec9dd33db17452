// SceneSource: the capability of every env that MuJoCo simulates (the
// manipulation tasks and benchmarks, the box world, the half-cheetah): its
// current scene, for rendering, and that scene's MJCF, for export. Callers
// find it behind wrappers with FindThroughWrappers<sim::SceneSource>(env)
// (core/wrapper.h), so that no caller needs to know the suites.
#ifndef MANYWORLDS_SIM_SCENE_SOURCE_H_
#define MANYWORLDS_SIM_SCENE_SOURCE_H_

#include <string>
#include <string_view>
#include <vector>

#include <mujoco/mujoco.h>

namespace manyworlds::sim {

// The MuJoCo model and data that simulate an env's current task. Both
// belong to the env: valid until its next SetTaskState, and the data
// changes with every step.
struct Scene {
  const mjModel* model = nullptr;
  const mjData* data = nullptr;
};

class SceneSource {
 public:
  virtual ~SceneSource() = default;

  // The current scene; both pointers are null while the env has none yet (a
  // benchmark or the box world before its first task state).
  virtual Scene ActiveScene() const = 0;
  // Writes the complete MJCF of the current task to `path` (atomically);
  // MuJoCo loads it on its own. Throws EpisodeStateError while there is no
  // scene, Error if writing fails.
  virtual void SaveSceneXml(const std::string& path) const = 0;
  // The camera a renderer uses unless told otherwise: a preset of
  // sim/render.h or a camera the model defines.
  virtual std::string_view default_camera() const { return "front"; }
  // The cameras every scene of this env defines, so that a camera name can be
  // checked before the env has a scene (a benchmark or the box world before
  // their first task state). Envs whose scene exists from construction need
  // not say.
  virtual std::vector<std::string> scene_cameras() const { return {}; }
};

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_SCENE_SOURCE_H_
