// PixelObservation: rendered frames as the pixel observation of a MuJoCo env
// (the registry option obs=pixels). After every reset and step the env's
// current scene (sim::SceneSource, found through wrappers) is rendered from
// one camera into out.pixels: uint8 RGB, channels first (3, height, width),
// rows top to bottom, as MTEnv's and dmc2gym's pixel observations. env_obs
// stays the env's proprioceptive state (asymmetric critics read it).
//
// Rendering goes through the calling thread's renderer (ThreadRenderer): a
// batched executor with T threads holds T OpenGL contexts, and envs whose
// models share meshes and textures share their GL resources (the model's
// ModelRenderKey, recomputed when the task changes).
//
// Quality: without shadows or multisampling unless settings.full_quality
// (RenderQuality in render.h: about 10x faster on llvmpipe).
//
// Backend: OSMesa, or EGL with MANYWORLDS_GL=egl (render.h). Mesa's llvmpipe
// would start its own render threads in every context; pixel observations set
// LP_NUM_THREADS=0 unless the user set it, so that rendering stays on the
// executor's threads (one layer of parallelism per core).
#ifndef MANYWORLDS_SIM_PIXEL_OBSERVATION_H_
#define MANYWORLDS_SIM_PIXEL_OBSERVATION_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "manyworlds/core/registry.h"
#include "manyworlds/core/wrapper.h"
#include "manyworlds/sim/render.h"
#include "manyworlds/sim/scene_source.h"

namespace manyworlds::sim {

class PixelObservation : public Wrapper {
 public:
  // Throws ConfigError if the env has no MuJoCo scene, for a size outside
  // [1, 4096] or an unknown camera (checked against the scene when there is
  // one, else at the first render); RenderError if this build or machine
  // cannot render (naming the backend).
  PixelObservation(std::unique_ptr<Env> inner, const PixelSettings& settings);

  const std::string& camera() const { return camera_; }

 protected:
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  void Render(std::span<uint8_t> out);
  RenderQuality Quality() const;

  const SceneSource* source_;
  int width_, height_;
  std::string camera_;
  bool full_quality_;
  const void* keyed_model_ = nullptr;  // the model model_key_ belongs to
  uint64_t model_key_ = 0;
  bool key_stale_ = true;              // the task changed since the key was made
  std::vector<uint8_t> rgb_;           // height x width x 3, as rendered
};

// The factory the default registry installs for obs=pixels.
std::unique_ptr<Env> MakePixelObservation(std::unique_ptr<Env> env, const PixelSettings& settings);

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_PIXEL_OBSERVATION_H_
