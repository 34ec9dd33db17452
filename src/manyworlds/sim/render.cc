#include "manyworlds/sim/render.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <utility>

#include <GL/osmesa.h>

#include "manyworlds/core/registry.h"
#include "manyworlds/sim/model.h"
#include "manyworlds/sim/mujoco_error.h"

namespace manyworlds::sim {
namespace {

// A camera preset: a free camera aimed at a fixed point, or, with `body`
// set, at that body's origin plus `lookat` (world frame), every frame.
struct CameraPreset {
  const char* name;
  const char* body;  // nullptr: fixed look-at point
  std::array<double, 3> lookat;
  double distance, azimuth, elevation;  // metres, degrees (MuJoCo's convention)
};

// MuJoCo's free camera sits at lookat - distance * forward, forward =
// (cos el cos az, cos el sin az, sin el): azimuth -90 looks along -y (from
// the far side of the table at the robot), 180 along -x, elevation < 0 down.
constexpr CameraPreset kPresets[] = {
    // across the table, a little to the side so that the arm has depth
    {"front", nullptr, {0.0, 0.62, 0.30}, 1.9, -72.0, -24.0},
    // steeply down from the side (+x): the arm, in the plane x = 0, does not
    // hide the hand as it does from straight above
    {"top", nullptr, {0.0, 0.62, 0.10}, 1.8, 180.0, -70.0},
    {"side", nullptr, {0.0, 0.55, 0.30}, 1.8, 180.0, -18.0},
    // from the side (+x; the fingers close along y), down at the finger tips
    {"gripper", "hand", {0.0, 0.0, -0.06}, 0.5, 180.0, -25.0},
};

const CameraPreset* FindPreset(std::string_view name) {
  for (const CameraPreset& p : kPresets) {
    if (name == p.name) return &p;
  }
  return nullptr;
}

// Sizes that tell models apart when a freed model's address is reused (a
// cheap guard; ForgetModel is the reliable way).
std::array<int, 7> ModelSizes(const mjModel* m) {
  return {m->nbody, m->ngeom, m->nmesh, m->ntex, m->nskin, m->nhfield, m->nbuffer};
}

// Visual options: MuJoCo's defaults (geom and site groups 0-2, no contact
// or joint decorations).
mjvOption DefaultOption() {
  mjvOption opt;
  mjv_defaultOption(&opt);
  return opt;
}

}  // namespace

const std::vector<std::string>& CameraPresetNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const CameraPreset& p : kPresets) out.emplace_back(p.name);
    return out;
  }();
  return names;
}

std::vector<std::string> CameraNames(const mjModel* model) {
  std::vector<std::string> names = CameraPresetNames();
  for (int i = 0; i < model->ncam; ++i) {
    const char* name = model->names + model->name_camadr[i];
    if (*name != '\0' && !FindPreset(name)) names.emplace_back(name);
  }
  return names;
}

struct Renderer::Gl {
  OSMesaContext context = nullptr;
  std::vector<unsigned char> window;  // OSMesa's default framebuffer (unused)
  // per model
  const mjModel* model = nullptr;
  std::array<int, 7> sizes{};  // ModelSizes(model)
  bool has_context = false;
  mjrContext con;
  mjvScene scene;
  DataPtr scratch;
  mjvOption option = DefaultOption();
  std::vector<uint8_t> row;  // for flipping

  void MakeCurrent(int width, int height) {
    if (!OSMesaMakeCurrent(context, window.data(), GL_UNSIGNED_BYTE, width, height)) {
      throw RenderError("OSMesaMakeCurrent failed for a " + std::to_string(width) + "x" +
                        std::to_string(height) + " buffer");
    }
  }

  void FreeModel() {
    if (has_context) {
      mjr_freeContext(&con);
      mjv_freeScene(&scene);
      has_context = false;
    }
    scratch.reset();
    model = nullptr;
  }

  ~Gl() {
    if (context) {
      // mjr_freeContext deletes GL objects: the context must be current
      if (has_context) OSMesaMakeCurrent(context, window.data(), GL_UNSIGNED_BYTE, 1, 1);
      FreeModel();
      OSMesaDestroyContext(context);
    }
  }
};

Renderer::Renderer(int width, int height) : width_(width), height_(height) {
  if (width < 1 || height < 1 || width > kMaxSize || height > kMaxSize) {
    throw ConfigError("image size " + std::to_string(width) + "x" + std::to_string(height) +
                      " is not allowed: width and height must be in [1, " +
                      std::to_string(kMaxSize) + "]");
  }
  // Mesa 22's OSMesa segfaults in OSMesaCreateContext when GALLIUM_DRIVER
  // names a driver it has no software screen for (zink, virpipe, typos)
  if (const char* driver = std::getenv("GALLIUM_DRIVER");
      driver && *driver && std::strcmp(driver, "llvmpipe") != 0 &&
      std::strcmp(driver, "softpipe") != 0) {
    throw RenderError(std::string("GALLIUM_DRIVER=") + driver +
                      " is set: OSMesa renders only with llvmpipe or softpipe (and Mesa "
                      "crashes with other values); unset it or set it to llvmpipe");
  }
  InstallMujocoHandlers();
  gl_ = std::make_unique<Gl>();
  // RGBA colour, 24-bit depth, 8-bit stencil, compatibility profile (MuJoCo
  // 2.2.2 draws with the fixed-function pipeline).
  gl_->context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  if (!gl_->context) {
    throw RenderError(
        "could not create an OSMesa (offscreen OpenGL) context; is Mesa's libOSMesa working? "
        "(Debian: apt-get install libosmesa6)");
  }
  gl_->window.resize(static_cast<size_t>(width) * height * 4);
  mjr_defaultContext(&gl_->con);
  mjv_defaultScene(&gl_->scene);
}

Renderer::~Renderer() = default;

void Renderer::ForgetModel() {
  gl_->MakeCurrent(width_, height_);
  gl_->FreeModel();
}

void Renderer::Prepare(const mjModel* model) {
  gl_->MakeCurrent(width_, height_);
  if (model == gl_->model && ModelSizes(model) == gl_->sizes) return;
  gl_->FreeModel();

  // The offscreen framebuffer gets its size from the model's <visual>
  // settings. Set them on a shallow copy of the struct: mjr_makeContext only
  // reads the model and keeps no pointer to it.
  mjModel sized = *model;
  sized.vis.global.offwidth = width_;
  sized.vis.global.offheight = height_;
  mjr_defaultContext(&gl_->con);
  try {
    mjr_makeContext(&sized, &gl_->con, mjFONTSCALE_100);
  } catch (const MujocoError& e) {
    mjr_freeContext(&gl_->con);
    std::string message = std::string("could not set up MuJoCo rendering: ") + e.what();
    if (std::string_view(e.what()).find("gladLoadGL") != std::string_view::npos &&
        dlsym(RTLD_DEFAULT, "eglGetProcAddress") != nullptr) {
      message +=
          " (libEGL is loaded in this process: MuJoCo 2.2.2 then loads GL functions through "
          "EGL, which cannot reach the OSMesa context; do not link libEGL into a program that "
          "renders with OSMesa)";
    }
    throw RenderError(message);
  }
  gl_->has_context = true;
  mjv_defaultScene(&gl_->scene);
  mjv_makeScene(model, &gl_->scene, std::max(1000, 2 * (model->ngeom + model->nsite)));
  mjr_setBuffer(mjFB_OFFSCREEN, &gl_->con);
  if (gl_->con.currentBuffer != mjFB_OFFSCREEN || gl_->con.offWidth != width_ ||
      gl_->con.offHeight != height_) {
    gl_->FreeModel();
    throw RenderError("the OpenGL context has no usable offscreen framebuffer of " +
                      std::to_string(width_) + "x" + std::to_string(height_));
  }
  gl_->scratch = MakeData(model);
  gl_->model = model;
  gl_->sizes = ModelSizes(model);
}

mjvCamera Renderer::ResolveCamera(const mjModel* model, const mjData* data,
                                  std::string_view camera) const {
  mjvCamera cam;
  mjv_defaultCamera(&cam);
  // a model's own camera wins over a preset of the same name, so generated
  // scenes (the box world) can frame their own "top"
  const int id = mj_name2id(model, mjOBJ_CAMERA, std::string(camera).c_str());
  if (id >= 0) {
    cam.type = mjCAMERA_FIXED;
    cam.fixedcamid = id;
    return cam;
  }
  if (const CameraPreset* preset = FindPreset(camera)) {
    cam.type = mjCAMERA_FREE;
    cam.distance = preset->distance;
    cam.azimuth = preset->azimuth;
    cam.elevation = preset->elevation;
    for (int k = 0; k < 3; ++k) cam.lookat[k] = preset->lookat[k];
    if (preset->body) {
      const int body = mj_name2id(model, mjOBJ_BODY, preset->body);
      if (body < 0) {
        throw ConfigError("camera '" + std::string(camera) + "' follows the body '" +
                          preset->body + "', which this model does not have");
      }
      for (int k = 0; k < 3; ++k) cam.lookat[k] += data->xpos[3 * body + k];
    }
    return cam;
  }
  const std::vector<std::string> names = CameraNames(model);
  std::string allowed;
  for (const std::string& n : names) allowed += (allowed.empty() ? "" : ", ") + n;
  throw ConfigError("unknown camera '" + std::string(camera) + "'" +
                    SuggestNearest(camera, names) + "; allowed: " + allowed);
}

void Renderer::Render(const mjModel* model, const mjData* data, std::string_view camera,
                      std::span<uint8_t> rgb) {
  const size_t row_bytes = static_cast<size_t>(width_) * 3;
  if (rgb.size() != row_bytes * height_) {
    throw Error("Renderer::Render: the buffer holds " + std::to_string(rgb.size()) +
                " bytes, a " + std::to_string(width_) + "x" + std::to_string(height_) +
                " RGB image needs " + std::to_string(row_bytes * height_));
  }
  mjvCamera cam = ResolveCamera(model, data, camera);
  Prepare(model);

  mjData* scratch = gl_->scratch.get();
  mj_copyData(scratch, model, data);
  mjv_updateScene(model, scratch, &gl_->option, nullptr, &cam, mjCAT_ALL, &gl_->scene);
  const mjrRect viewport{0, 0, width_, height_};
  mjr_setBuffer(mjFB_OFFSCREEN, &gl_->con);
  mjr_render(viewport, &gl_->scene, &gl_->con);
  mjr_readPixels(rgb.data(), nullptr, viewport, &gl_->con);

  // OpenGL's rows run bottom to top
  gl_->row.resize(row_bytes);
  for (int top = 0, bottom = height_ - 1; top < bottom; ++top, --bottom) {
    uint8_t* a = rgb.data() + top * row_bytes;
    uint8_t* b = rgb.data() + bottom * row_bytes;
    std::memcpy(gl_->row.data(), a, row_bytes);
    std::memcpy(a, b, row_bytes);
    std::memcpy(b, gl_->row.data(), row_bytes);
  }
}

std::vector<uint8_t> Renderer::Render(const mjModel* model, const mjData* data,
                                      std::string_view camera) {
  std::vector<uint8_t> rgb(static_cast<size_t>(width_) * height_ * 3);
  Render(model, data, camera, rgb);
  return rgb;
}

}  // namespace manyworlds::sim
