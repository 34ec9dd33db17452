// Offscreen rendering of a MuJoCo scene to an RGB image, without a display.
//
//   sim::Renderer renderer(640, 480);          // OSMesa context + mjrContext
//   std::vector<uint8_t> rgb = renderer.Render(model, data, "front");
//   // rgb: 640 x 480 x 3 bytes, row 0 = top row of the image
//
// The renderer owns one OSMesa (software OpenGL, Mesa's llvmpipe) context
// and, for the model it last rendered, one mjrContext (the model's meshes,
// textures and an offscreen framebuffer of exactly width x height) and one
// scratch mjData. Render() copies the caller's mjData into the scratch one
// (mjv_updateScene writes to the mjData it is given, the caller's stays
// untouched), builds the scene and reads the pixels back. The first frame
// of a model sets up its GL resources (about 0.3 s with llvmpipe; a new
// model, e.g. another benchmark member, repeats that); later frames of the
// Sawyer scenes take 25-35 ms at 640x480 on two cores (4x multisampling,
// the model's default).
//
// Cameras, by name:
//   front    free camera across the table from the robot, slightly to -x
//   top      free camera high above the table's side (+x), 70 degrees down
//   side     free camera at the table's side (+x), looking along -x
//   gripper  follows the body "hand" from the side, looking down at the
//            finger tips (aimed 6 cm below the hand, 0.5 m away)
//   any camera defined in the model (<camera name=...>); a model camera
//   wins over a preset of the same name (the box world defines its own
//   top and perspective)
// The free presets are framed for the Sawyer scenes (table top z = 0, robot
// base at y = 0.15, workspace around (0, 0.6..0.9, 0..0.3)).
//
// GL function loading, MuJoCo 2.2.2: mjr_makeContext loads the GL entry
// points (glad) with the first of eglGetProcAddress, OSMesaGetProcAddress,
// glXGetProcAddressARB that dlsym finds in the process's global scope, and
// needs a current context while doing so. The renderer therefore makes its
// OSMesa context current before every MuJoCo GL call, and libOSMesa is
// linked into the program (global scope). If libEGL is also loaded in the
// process, MuJoCo picks EGL, whose entry points do not reach an OSMesa
// context, and fails with "gladLoadGL error"; the RenderError then says so.
// Mesa itself crashes when GALLIUM_DRIVER names anything but llvmpipe or
// softpipe, so the constructor refuses other values.
//
// Backends, chosen once per process by MANYWORLDS_GL: `osmesa` (default;
// Mesa's software rasteriser, any machine) or `egl` (libEGL opened at run
// time with global symbols, so that MuJoCo's loader takes EGL's entry points;
// a GPU's EGL device first, else Mesa's software device or surfaceless
// platform; contexts without a surface, MuJoCo draws into its own offscreen
// framebuffer). One process cannot mix them (see above). On Mesa's software
// device EGL renders the same bytes as OSMesa (tests/cli/cli_test.cc).
//
// Not thread-safe: one renderer per thread (the OSMesa context is made
// current on the calling thread). Several renderers may coexist.
//
// Several models: the GL resources of up to kMaxModels models are kept (the
// least recently used one goes first), so that one renderer serves a batch of
// envs on different tasks. A model is recognised either by its address (and
// sizes) or, in the keyed Render overload, by a caller's key that stands for
// everything mjr_makeContext uploads (ModelRenderKey): envs whose models share
// meshes and textures then share one set of GL resources.
//
// ThreadRenderer(w, h) is the renderer of the calling thread for one image
// size: pixel observations (pixel_observation.h) use it, so that N envs
// stepped by T executor threads hold T OpenGL contexts, not N.
#ifndef MANYWORLDS_SIM_RENDER_H_
#define MANYWORLDS_SIM_RENDER_H_

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <mujoco/mujoco.h>

#include "manyworlds/core/error.h"

namespace manyworlds::sim {

// No offscreen OpenGL context could be made or used (OSMesa missing or
// failing, MuJoCo unable to load GL functions).
class RenderError : public Error {
 public:
  using Error::Error;
};

// The camera presets, in the order listed above.
const std::vector<std::string>& CameraPresetNames();

// Preset names followed by the names of the model's cameras.
std::vector<std::string> CameraNames(const mjModel* model);

// A key for the GL resources of a model: a hash of its sizes, its <visual>
// settings and the data mjr_makeContext uploads (meshes, skins, height
// fields, textures). Two models with the same key render alike from one
// mjrContext. Reads every mesh vertex: compute it when a model changes, not
// every frame.
uint64_t ModelRenderKey(const mjModel* model);

// kFull renders as the model asks (shadows, its multisampling: MuJoCo's
// default 4x); kFast without shadows or multisampling. On llvmpipe the shadow
// map (4096 x 4096 by default) and multisampling cost most of a small frame:
// an 84 x 84 Sawyer frame takes about 25 ms full and 2 ms fast (2026-11-28,
// docs/benchmarks.md).
enum class RenderQuality { kFull, kFast };

class Renderer {
 public:
  // Image sizes from 1 to kMaxSize pixels per side.
  static constexpr int kMaxSize = 4096;
  // Models whose GL resources are kept at once.
  static constexpr int kMaxModels = 64;

  // Creates the OSMesa context. Throws ConfigError for a bad size,
  // RenderError if no context can be made.
  Renderer(int width, int height, RenderQuality quality = RenderQuality::kFull);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  RenderQuality quality() const { return quality_; }

  // Renders `data` (of `model`) seen from `camera` into `rgb` (width x
  // height x 3 bytes, rows top to bottom). Neither is modified; both must be
  // valid for the call only. The GL resources are kept for the last model,
  // recognised by its address (and sizes): call ForgetModel() after freeing
  // a model if another one may be allocated at the same address.
  // Throws ConfigError for an unknown camera (listing the allowed names) or
  // a preset whose body the model lacks, Error for a buffer of the wrong
  // size, RenderError or MujocoError if rendering fails.
  void Render(const mjModel* model, const mjData* data, std::string_view camera,
              std::span<uint8_t> rgb);
  std::vector<uint8_t> Render(const mjModel* model, const mjData* data, std::string_view camera);
  // As above, with the model recognised by `model_key` (ModelRenderKey).
  void Render(const mjModel* model, const mjData* data, std::string_view camera,
              std::span<uint8_t> rgb, uint64_t model_key);

  // Drops the per-model GL resources; the next Render rebuilds them.
  void ForgetModel();
  // Models whose GL resources are held now.
  int cached_models() const;

 private:
  struct Gl;  // OSMesa and MuJoCo GL state (keeps GL headers out of here)

  struct Entry;
  // The GL resources for a model (made current first), built if missing.
  Entry& Prepare(const mjModel* model, uint64_t key);
  // The MuJoCo camera for a name; body-relative presets read data->xpos.
  mjvCamera ResolveCamera(const mjModel* model, const mjData* data, std::string_view camera) const;

  int width_, height_;
  RenderQuality quality_;
  std::unique_ptr<Gl> gl_;
};

// The calling thread's renderer for width x height images, made on first use
// (ConfigError / RenderError as the constructor) and freed when the thread
// ends. Not to be kept past the thread's end.
Renderer& ThreadRenderer(int width, int height, RenderQuality quality);

// What renders offscreen in this process: the backend and, once a renderer
// was made, its OpenGL renderer string, e.g. "OSMesa (llvmpipe (LLVM 15.0.6,
// 256 bits))" or "EGL, device 0 (NVIDIA H100 ...)". For logs.
std::string RenderBackendName();

}  // namespace manyworlds::sim

#endif  // MANYWORLDS_SIM_RENDER_H_
