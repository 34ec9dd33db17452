#include "manyworlds/sim/pixel_observation.h"

#include <algorithm>
#include <cstdlib>

#include "manyworlds/core/error.h"
#include "manyworlds/sim/render.h"  // RenderError; the renderer itself only with OSMesa

namespace manyworlds::sim {
namespace {

constexpr int kMaxPixelSize = 4096;

std::unique_ptr<Env> CheckPixelEnv(std::unique_ptr<Env> inner, const PixelSettings& settings) {
  if (!inner) throw Error("wrapper pixels needs an env, got null");
  if (settings.width < 1 || settings.height < 1 || settings.width > kMaxPixelSize ||
      settings.height > kMaxPixelSize) {
    throw ConfigError("env '" + inner->spec().id + "': pixel observations of " +
                      std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                      " are not allowed: width and height must be in [1, " +
                      std::to_string(kMaxPixelSize) + "]");
  }
  if (FindThroughWrappers<SceneSource>(*inner) == nullptr) {
    throw ConfigError("env '" + inner->spec().id +
                      "' has no MuJoCo scene; obs=pixels works for the MuJoCo envs "
                      "(manipulation tasks and benchmarks, box-world-*, half-cheetah-*, the "
                      "DeepMind-Control-style suites)");
  }
#ifndef MANYWORLDS_HAS_RENDER
  throw RenderError("env '" + inner->spec().id +
                    "': obs=pixels needs an offscreen renderer, and this build has none (it was "
                    "built without OSMesa: install libosmesa6-dev and rebuild)");
#endif
  return inner;
}

}  // namespace

PixelObservation::PixelObservation(std::unique_ptr<Env> inner, const PixelSettings& settings)
    : Wrapper(CheckPixelEnv(std::move(inner), settings), "pixels"),
      source_(FindThroughWrappers<SceneSource>(this->inner())),
      width_(static_cast<int>(settings.width)),
      height_(static_cast<int>(settings.height)),
      camera_(settings.camera.empty() ? std::string(source_->default_camera()) : settings.camera),
      full_quality_(settings.full_quality) {
  mutable_spec().pixel_space = Space::Box(0.0f, 255.0f, {3, height_, width_});
  rgb_.resize(static_cast<size_t>(width_) * height_ * 3);
#ifdef MANYWORLDS_HAS_RENDER
  // the scene's cameras, or before there is one, the presets and the cameras every scene has
  std::vector<std::string> names;
  if (const Scene scene = source_->ActiveScene(); scene.model != nullptr) {
    names = CameraNames(scene.model);
  } else {
    names = CameraPresetNames();
    for (const std::string& name : source_->scene_cameras()) {
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
  }
  if (std::find(names.begin(), names.end(), camera_) == names.end()) {
    std::string allowed;
    for (const std::string& n : names) allowed += (allowed.empty() ? "" : ", ") + n;
    throw ConfigError("env '" + spec().id + "': unknown camera '" + ShortenForMessage(camera_) +
                      "'; allowed: " + allowed);
  }
  // llvmpipe's own threads would be a second layer of parallelism under the executor's
  setenv("LP_NUM_THREADS", "0", /*overwrite=*/0);
  // a machine that cannot render fails here, not in the middle of a run
  ThreadRenderer(width_, height_, Quality());
#endif
}

RenderQuality PixelObservation::Quality() const {
  return full_quality_ ? RenderQuality::kFull : RenderQuality::kFast;
}

void PixelObservation::DoSetTaskState(const TaskState& state) {
  Wrapper::DoSetTaskState(state);
  key_stale_ = true;
}

void PixelObservation::DoReset(const ObsView& out) {
  Wrapper::DoReset(ObsView{out.env_obs, out.task_obs, {}});
  Render(out.pixels);
}

void PixelObservation::DoStep(std::span<const float> action, const StepView& out) {
  StepView inner_out = out;
  inner_out.pixels = {};
  Wrapper::DoStep(action, inner_out);
  Render(out.pixels);
}

void PixelObservation::Render(std::span<uint8_t> out) {
#ifdef MANYWORLDS_HAS_RENDER
  const Scene scene = source_->ActiveScene();
  if (scene.model == nullptr) {
    throw EpisodeStateError("env '" + spec().id + "': no scene to render before a task is set");
  }
  // a task change may rebuild the model (at the same address, too)
  if (key_stale_ || keyed_model_ != scene.model) {
    model_key_ = ModelRenderKey(scene.model);
    keyed_model_ = scene.model;
    key_stale_ = false;
  }
  ThreadRenderer(width_, height_, Quality()).Render(scene.model, scene.data, camera_, rgb_, model_key_);
  // (height, width, 3) -> (3, height, width)
  const size_t plane = static_cast<size_t>(width_) * height_;
  for (size_t p = 0; p < plane; ++p) {
    out[p] = rgb_[3 * p];
    out[plane + p] = rgb_[3 * p + 1];
    out[2 * plane + p] = rgb_[3 * p + 2];
  }
#else
  (void)out;
#endif
}

std::unique_ptr<Env> MakePixelObservation(std::unique_ptr<Env> env, const PixelSettings& settings) {
  return std::make_unique<PixelObservation>(std::move(env), settings);
}

}  // namespace manyworlds::sim
