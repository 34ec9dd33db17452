#include "manyworlds/sim/render.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <sstream>
#include <type_traits>
#include <utility>

#include <GL/osmesa.h>
// EGL's headers only (Debian: libegl-dev); libEGL itself is opened at run time, never linked
#if __has_include(<EGL/egl.h>) && __has_include(<EGL/eglext.h>)
#include <EGL/egl.h>
#include <EGL/eglext.h>
#define MANYWORLDS_RENDER_EGL 1
#endif

#include "manyworlds/core/hash.h"
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

// The GL resources of one model.
struct Renderer::Entry {
  uint64_t key = 0;
  uint64_t last_used = 0;
  mjrContext con;
  mjvScene scene;
  DataPtr scratch;  // mjv_updateScene writes to the mjData it gets; callers' stay untouched

  Entry() {
    mjr_defaultContext(&con);
    mjv_defaultScene(&scene);
  }
  // The owning context must be current.
  void Free() {
    mjr_freeContext(&con);
    mjv_freeScene(&scene);
  }
};

namespace {

// The backend of this process, chosen once from MANYWORLDS_GL (see render.h).
enum class Backend { kOsmesa, kEgl };

Backend ChosenBackend() {
  static const Backend backend = [] {
    const char* value = std::getenv("MANYWORLDS_GL");
    const std::string name = value == nullptr ? "" : value;
    if (name.empty() || name == "osmesa") return Backend::kOsmesa;
    if (name == "egl") return Backend::kEgl;
    throw RenderError("MANYWORLDS_GL=" + ShortenForMessage(name) +
                      " is not a rendering backend; allowed: osmesa (default: software, any "
                      "machine), egl (a GPU's driver, or Mesa's surfaceless software device)");
  }();
  return backend;
}

// What rendered, for RenderBackendName(); set when the first context is made.
std::mutex& BackendNameMutex() {
  static std::mutex mutex;
  return mutex;
}
std::string& BackendName() {
  static std::string name;
  return name;
}

#ifdef MANYWORLDS_RENDER_EGL
// libEGL, opened at run time with its symbols global (MuJoCo 2.2.2's GL loader looks for
// eglGetProcAddress there), only when MANYWORLDS_GL=egl: a process that renders with OSMesa
// must not have it loaded (render.h).
struct Egl {
  PFNEGLGETPROCADDRESSPROC GetProcAddress = nullptr;
  PFNEGLGETERRORPROC GetError = nullptr;
  PFNEGLINITIALIZEPROC Initialize = nullptr;
  PFNEGLBINDAPIPROC BindAPI = nullptr;
  PFNEGLCHOOSECONFIGPROC ChooseConfig = nullptr;
  PFNEGLCREATECONTEXTPROC CreateContext = nullptr;
  PFNEGLMAKECURRENTPROC MakeCurrent = nullptr;
  PFNEGLDESTROYCONTEXTPROC DestroyContext = nullptr;
  PFNEGLQUERYSTRINGPROC QueryString = nullptr;
  PFNEGLQUERYDEVICESEXTPROC QueryDevices = nullptr;
  PFNEGLQUERYDEVICESTRINGEXTPROC QueryDeviceString = nullptr;
  PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplay = nullptr;
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLConfig config = nullptr;
  std::string device;  // which display was taken
};

std::string EglErrorText(const Egl& egl) {
  std::ostringstream out;
  out << "EGL error 0x" << std::hex << (egl.GetError ? egl.GetError() : 0);
  return out.str();
}

// The process's EGL display and config: a GPU device if EGL lists one, else Mesa's software
// device or surfaceless platform. Throws RenderError naming what is missing.
const Egl& LoadEgl() {
  static const Egl egl = [] {
    Egl e;
    void* library = dlopen("libEGL.so.1", RTLD_NOW | RTLD_GLOBAL);
    if (library == nullptr) {
      throw RenderError(std::string("MANYWORLDS_GL=egl: cannot load libEGL.so.1 (") + dlerror() +
                        "); install a GPU driver's EGL or Debian's libegl1 and libegl-mesa0, or "
                        "unset MANYWORLDS_GL to render with OSMesa");
    }
    auto load = [&](auto& fn, const char* name) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(dlsym(library, name));
      if (fn == nullptr) throw RenderError(std::string("MANYWORLDS_GL=egl: libEGL lacks ") + name);
    };
    load(e.GetProcAddress, "eglGetProcAddress");
    load(e.GetError, "eglGetError");
    load(e.Initialize, "eglInitialize");
    load(e.BindAPI, "eglBindAPI");
    load(e.ChooseConfig, "eglChooseConfig");
    load(e.CreateContext, "eglCreateContext");
    load(e.MakeCurrent, "eglMakeCurrent");
    load(e.DestroyContext, "eglDestroyContext");
    load(e.QueryString, "eglQueryString");
    e.QueryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(e.GetProcAddress("eglQueryDevicesEXT"));
    e.QueryDeviceString =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(e.GetProcAddress("eglQueryDeviceStringEXT"));
    e.GetPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(e.GetProcAddress("eglGetPlatformDisplayEXT"));
    if (e.GetPlatformDisplay == nullptr) {
      throw RenderError("MANYWORLDS_GL=egl: this EGL has no eglGetPlatformDisplayEXT (needed for "
                        "rendering without a window system)");
    }
    // hardware devices first (a GPU), then software ones (Mesa's llvmpipe)
    std::vector<std::pair<EGLDisplay, std::string>> candidates;
    if (e.QueryDevices != nullptr) {
      EGLDeviceEXT devices[16];
      EGLint count = 0;
      if (e.QueryDevices(16, devices, &count)) {
        std::vector<std::pair<EGLDisplay, std::string>> software;
        for (EGLint i = 0; i < count; ++i) {
          const char* extensions =
              e.QueryDeviceString ? e.QueryDeviceString(devices[i], EGL_EXTENSIONS) : nullptr;
          const bool is_software =
              extensions && std::strstr(extensions, "EGL_MESA_device_software") != nullptr;
          EGLDisplay d = e.GetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
          if (d == EGL_NO_DISPLAY) continue;
          (is_software ? software : candidates)
              .emplace_back(d, "device " + std::to_string(i) + (is_software ? " (software)" : ""));
        }
        candidates.insert(candidates.end(), software.begin(), software.end());
      }
    }
    if (EGLDisplay d = e.GetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        d != EGL_NO_DISPLAY) {
      candidates.emplace_back(d, "Mesa surfaceless platform");
    }
    for (const auto& [display, name] : candidates) {
      EGLint major = 0, minor = 0;
      if (!e.Initialize(display, &major, &minor)) continue;
      // no window system: pbuffer configs (the default asks for window ones)
      const EGLint attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RED_SIZE, 8,
                                   EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_DEPTH_SIZE, 24,
                                   EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint configs = 0;
      if (!e.ChooseConfig(display, attributes, &e.config, 1, &configs) || configs < 1) continue;
      e.display = display;
      e.device = name;
      break;
    }
    if (e.display == EGL_NO_DISPLAY) {
      throw RenderError("MANYWORLDS_GL=egl: no EGL display with an OpenGL config (" +
                        std::to_string(candidates.size()) +
                        " tried); unset MANYWORLDS_GL to render with OSMesa");
    }
    if (!e.BindAPI(EGL_OPENGL_API)) {
      throw RenderError("MANYWORLDS_GL=egl: eglBindAPI(EGL_OPENGL_API) failed (" + EglErrorText(e) + ")");
    }
    return e;
  }();
  return egl;
}

#endif  // MANYWORLDS_RENDER_EGL

}  // namespace

struct Renderer::Gl {
  Backend backend = Backend::kOsmesa;
  OSMesaContext context = nullptr;
  std::vector<unsigned char> window;  // OSMesa's default framebuffer (unused)
#ifdef MANYWORLDS_RENDER_EGL
  EGLContext egl_context = EGL_NO_CONTEXT;
#endif
  std::vector<std::unique_ptr<Entry>> entries;
  uint64_t clock = 0;
  mjvOption option = DefaultOption();
  std::vector<uint8_t> row;  // for flipping

  void MakeCurrent(int width, int height) {
#ifdef MANYWORLDS_RENDER_EGL
    if (backend == Backend::kEgl) {
      // MuJoCo draws into its own offscreen framebuffer: no surface needed
      const Egl& egl = LoadEgl();
      if (!egl.MakeCurrent(egl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_context)) {
        throw RenderError("eglMakeCurrent failed (" + EglErrorText(egl) + ")");
      }
      return;
    }
#endif
    if (!OSMesaMakeCurrent(context, window.data(), GL_UNSIGNED_BYTE, width, height)) {
      throw RenderError("OSMesaMakeCurrent failed for a " + std::to_string(width) + "x" +
                        std::to_string(height) + " buffer");
    }
  }

  void FreeAll() {
    for (auto& e : entries) e->Free();
    entries.clear();
  }

  ~Gl() {
#ifdef MANYWORLDS_RENDER_EGL
    if (egl_context != EGL_NO_CONTEXT) {
      const Egl& egl = LoadEgl();
      if (!entries.empty()) egl.MakeCurrent(egl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, egl_context);
      FreeAll();
      egl.MakeCurrent(egl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      egl.DestroyContext(egl.display, egl_context);
    }
#endif
    if (context) {
      // mjr_freeContext deletes GL objects: the context must be current
      if (!entries.empty()) OSMesaMakeCurrent(context, window.data(), GL_UNSIGNED_BYTE, 1, 1);
      FreeAll();
      OSMesaDestroyContext(context);
    }
  }
};

namespace {

// MuJoCo 2.2.2 loads GL entry points into process-wide pointers in every
// mjr_makeContext, and Mesa's context creation is not documented as
// thread-safe: renderers of different threads take turns for both.
std::mutex& GlSetupMutex() {
  static std::mutex mutex;
  return mutex;
}

// Records what renders, "OSMesa (llvmpipe (LLVM 15.0.6, 256 bits))" or "EGL, device 0 (NVIDIA
// H100 ...)": the backend and the current context's GL_RENDERER.
void NoteBackend(const std::string& backend) {
  const std::lock_guard<std::mutex> lock(BackendNameMutex());
  if (!BackendName().empty()) return;
  using GetString = const unsigned char* (*)(unsigned int);
  GetString get_string = nullptr;
  if (backend.rfind("EGL", 0) == 0) {
#ifdef MANYWORLDS_RENDER_EGL
    get_string = reinterpret_cast<GetString>(LoadEgl().GetProcAddress("glGetString"));
#endif
  } else {
    get_string = reinterpret_cast<GetString>(OSMesaGetProcAddress("glGetString"));
  }
  const unsigned char* renderer = get_string ? get_string(GL_RENDERER) : nullptr;
  BackendName() = backend + " (" +
                  (renderer ? reinterpret_cast<const char*>(renderer) : "renderer unknown") + ")";
}


// A model recognised by its address and sizes (the unkeyed Render).
uint64_t AddressKey(const mjModel* m) {
  const auto address = reinterpret_cast<uintptr_t>(m);
  const std::array<int, 7> sizes = ModelSizes(m);
  uint64_t hash = Fnv1a(&address, sizeof address);
  return Fnv1a(sizes.data(), sizeof sizes, hash) | 1;  // odd: never a content key
}

}  // namespace

uint64_t ModelRenderKey(const mjModel* m) {
  uint64_t h = kFnv1aOffset;
  // every size of the model: the int fields from nq to nbuffer
  h = Fnv1a(&m->nq, reinterpret_cast<const char*>(&m->opt) - reinterpret_cast<const char*>(&m->nq),
            h);
  h = Fnv1a(&m->vis, sizeof m->vis, h);
  h = Fnv1a(m->mesh_vert, sizeof(float) * 3 * m->nmeshvert, h);
  h = Fnv1a(m->mesh_normal, sizeof(float) * 3 * m->nmeshvert, h);
  h = Fnv1a(m->mesh_texcoord, sizeof(float) * 2 * m->nmeshtexvert, h);
  h = Fnv1a(m->mesh_face, sizeof(int) * 3 * m->nmeshface, h);
  h = Fnv1a(m->skin_vert, sizeof(float) * 3 * m->nskinvert, h);
  h = Fnv1a(m->hfield_size, sizeof(mjtNum) * 4 * m->nhfield, h);
  h = Fnv1a(m->hfield_data, sizeof(float) * m->nhfielddata, h);
  h = Fnv1a(m->tex_type, sizeof(int) * m->ntex, h);
  h = Fnv1a(m->tex_height, sizeof(int) * m->ntex, h);
  h = Fnv1a(m->tex_width, sizeof(int) * m->ntex, h);
  h = Fnv1a(m->tex_rgb, m->ntexdata, h);
  return h & ~uint64_t{1};  // even: never an address key
}

Renderer::Renderer(int width, int height, RenderQuality quality)
    : width_(width), height_(height), quality_(quality) {
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
  gl_->backend = ChosenBackend();
  if (gl_->backend == Backend::kEgl) {
#ifndef MANYWORLDS_RENDER_EGL
    throw RenderError("MANYWORLDS_GL=egl: this build has no EGL support (EGL's headers, Debian's "
                      "libegl-dev, were missing when it was built); unset MANYWORLDS_GL");
#else
    const Egl& egl = LoadEgl();
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 1, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT, EGL_NONE};
    {
      const std::lock_guard<std::mutex> lock(GlSetupMutex());
      gl_->egl_context = egl.CreateContext(egl.display, egl.config, EGL_NO_CONTEXT, attributes);
    }
    if (gl_->egl_context == EGL_NO_CONTEXT) {
      throw RenderError("MANYWORLDS_GL=egl: could not create an OpenGL context (" +
                        EglErrorText(egl) + ")");
    }
    gl_->MakeCurrent(width, height);
    NoteBackend("EGL, " + egl.device);
    return;
#endif
  }
  {
    const std::lock_guard<std::mutex> lock(GlSetupMutex());
    // RGBA colour, 24-bit depth, 8-bit stencil, compatibility profile (MuJoCo
    // 2.2.2 draws with the fixed-function pipeline).
    gl_->context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  }
  if (!gl_->context) {
    throw RenderError(
        "could not create an OSMesa (offscreen OpenGL) context; is Mesa's libOSMesa working? "
        "(Debian: apt-get install libosmesa6)");
  }
  gl_->window.resize(static_cast<size_t>(width) * height * 4);
  gl_->MakeCurrent(width, height);
  NoteBackend("OSMesa");
}

Renderer::~Renderer() = default;

void Renderer::ForgetModel() {
  gl_->MakeCurrent(width_, height_);
  gl_->FreeAll();
}

int Renderer::cached_models() const { return static_cast<int>(gl_->entries.size()); }

Renderer::Entry& Renderer::Prepare(const mjModel* model, uint64_t key) {
  gl_->MakeCurrent(width_, height_);
  ++gl_->clock;
  for (auto& e : gl_->entries) {
    if (e->key == key) {
      e->last_used = gl_->clock;
      return *e;
    }
  }
  if (static_cast<int>(gl_->entries.size()) >= kMaxModels) {
    auto oldest = std::min_element(gl_->entries.begin(), gl_->entries.end(),
                                   [](const auto& a, const auto& b) {
                                     return a->last_used < b->last_used;
                                   });
    (*oldest)->Free();
    gl_->entries.erase(oldest);
  }
  auto entry = std::make_unique<Entry>();

  // The offscreen framebuffer gets its size from the model's <visual>
  // settings. Set them on a shallow copy of the struct: mjr_makeContext only
  // reads the model and keeps no pointer to it.
  mjModel sized = *model;
  sized.vis.global.offwidth = width_;
  sized.vis.global.offheight = height_;
  if (quality_ == RenderQuality::kFast) sized.vis.quality.offsamples = 0;
  try {
    const std::lock_guard<std::mutex> lock(GlSetupMutex());
    mjr_makeContext(&sized, &entry->con, mjFONTSCALE_100);
  } catch (const MujocoError& e) {
    mjr_freeContext(&entry->con);
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
  mjv_makeScene(model, &entry->scene, std::max(1000, 2 * (model->ngeom + model->nsite)));
  if (quality_ == RenderQuality::kFast) entry->scene.flags[mjRND_SHADOW] = 0;
  mjr_setBuffer(mjFB_OFFSCREEN, &entry->con);
  if (entry->con.currentBuffer != mjFB_OFFSCREEN || entry->con.offWidth != width_ ||
      entry->con.offHeight != height_) {
    entry->Free();
    throw RenderError("the OpenGL context has no usable offscreen framebuffer of " +
                      std::to_string(width_) + "x" + std::to_string(height_));
  }
  entry->scratch = MakeData(model);
  entry->key = key;
  entry->last_used = gl_->clock;
  gl_->entries.push_back(std::move(entry));
  return *gl_->entries.back();
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
  Render(model, data, camera, rgb, AddressKey(model));
}

void Renderer::Render(const mjModel* model, const mjData* data, std::string_view camera,
                      std::span<uint8_t> rgb, uint64_t model_key) {
  const size_t row_bytes = static_cast<size_t>(width_) * 3;
  if (rgb.size() != row_bytes * height_) {
    throw Error("Renderer::Render: the buffer holds " + std::to_string(rgb.size()) +
                " bytes, a " + std::to_string(width_) + "x" + std::to_string(height_) +
                " RGB image needs " + std::to_string(row_bytes * height_));
  }
  mjvCamera cam = ResolveCamera(model, data, camera);
  Entry& entry = Prepare(model, model_key);

  // a keyed entry may have been made from another model of equal sizes: the
  // scratch data fits every model with the same sizes
  mjData* scratch = entry.scratch.get();
  mj_copyData(scratch, model, data);
  mjv_updateScene(model, scratch, &gl_->option, nullptr, &cam, mjCAT_ALL, &entry.scene);
  const mjrRect viewport{0, 0, width_, height_};
  mjr_setBuffer(mjFB_OFFSCREEN, &entry.con);
  mjr_render(viewport, &entry.scene, &entry.con);
  mjr_readPixels(rgb.data(), nullptr, viewport, &entry.con);

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

Renderer& ThreadRenderer(int width, int height, RenderQuality quality) {
  // one renderer per thread, image size and quality; freed with the thread
  thread_local std::vector<std::unique_ptr<Renderer>> renderers;
  for (auto& r : renderers) {
    if (r->width() == width && r->height() == height && r->quality() == quality) return *r;
  }
  renderers.push_back(std::make_unique<Renderer>(width, height, quality));
  return *renderers.back();
}

std::string RenderBackendName() {
  const std::lock_guard<std::mutex> lock(BackendNameMutex());
  if (!BackendName().empty()) return BackendName();
  return ChosenBackend() == Backend::kEgl ? "EGL" : "OSMesa";
}

}  // namespace manyworlds::sim
