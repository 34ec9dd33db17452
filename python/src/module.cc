// manyworlds._core: the C++ side of the manyworlds Python package.
#include <dlfcn.h>

#include <exception>
#include <string>

#include <nlohmann/json.hpp>

#include "bindings.h"
#include "manyworlds/core/error.h"

#ifdef MANYWORLDS_PY_RENDER
// Declared here rather than through GL/osmesa.h: only its address is taken.
extern "C" void* OSMesaGetProcAddress(const char* name);
#endif

namespace manyworlds::python {
namespace {

// Python exception types, created once at import and kept for the life of
// the process (they are module attributes as well).
PyObject* g_error = nullptr;               // manyworlds.Error(RuntimeError)
PyObject* g_config_error = nullptr;        // manyworlds.ConfigError(ValueError)
PyObject* g_invalid_action_error = nullptr;// manyworlds.InvalidActionError(ValueError)
PyObject* g_task_state_error = nullptr;    // manyworlds.TaskStateError(ValueError)
PyObject* g_episode_state_error = nullptr; // manyworlds.EpisodeStateError(RuntimeError)

PyObject* NewException(py::module_& m, const char* name, PyObject* bases, const char* doc) {
  const std::string qualified = std::string("manyworlds.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases, nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.attr(name) = py::reinterpret_borrow<py::object>(type);
  return type;  // the new reference is kept for good
}

// MuJoCo 2.2.2 finds OSMesaGetProcAddress with dlsym in the global scope,
// but Python loads extension modules (and so their libOSMesa) with
// RTLD_LOCAL. Promoting libOSMesa to the global scope would promote its
// dependencies too, Mesa's libLLVM among them, and a library with its own
// LLVM loaded later (Triton, under PyTorch 2's optimizers) would crash
// binding to it. Instead the shim library next to this module, which has no
// dependencies and defines only OSMesaGetProcAddress, is opened with
// RTLD_GLOBAL and forwards to the real function (osmesa_shim.cc). Without
// the shim, rendering reports MuJoCo's "could not load GL" as an error.
void EnsureOsmesaGlobal() {
#ifdef MANYWORLDS_PY_RENDER
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&EnsureOsmesaGlobal), &info) == 0 || !info.dli_fname) return;
  std::string path = info.dli_fname;
  const size_t slash = path.rfind('/');
  path = (slash == std::string::npos ? std::string() : path.substr(0, slash + 1)) +
         MANYWORLDS_OSMESA_SHIM;
  void* shim = dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);  // kept for the process
  if (shim == nullptr) return;
  using ProcAddressFn = void* (*)(const char*);
  auto set = reinterpret_cast<void (*)(ProcAddressFn)>(dlsym(shim, "manyworlds_osmesa_shim_set"));
  if (set != nullptr) set(&OSMesaGetProcAddress);
#endif
}

}  // namespace
}  // namespace manyworlds::python

PYBIND11_MODULE(_core, m) {
  using namespace manyworlds::python;
  m.doc() = "C++ core of manyworlds: registry envs and the batched executor (no libtorch).";

  py::tuple runtime_bases = py::make_tuple(py::handle(PyExc_RuntimeError));
  g_error = NewException(m, "Error", runtime_bases.ptr(),
                         "A manyworlds failure while running (a C++ manyworlds::Error).");
  py::tuple value_bases = py::make_tuple(py::handle(PyExc_ValueError));
  g_config_error = NewException(m, "ConfigError", value_bases.ptr(),
                                "Unknown env id, unknown or ill-typed option, bad option value.");
  g_invalid_action_error = NewException(
      m, "InvalidActionError", value_bases.ptr(),
      "An action of the wrong size, with NaN/inf, or outside a Discrete space.");
  g_task_state_error = NewException(m, "TaskStateError", value_bases.ptr(),
                                    "A task state that is malformed or belongs to another env.");
  py::tuple episode_bases = py::make_tuple(py::handle(g_error));
  g_episode_state_error = NewException(
      m, "EpisodeStateError", episode_bases.ptr(),
      "The episode protocol was broken: step before reset or after the end of an episode.");

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const manyworlds::InvalidActionError& e) {
      PyErr_SetString(g_invalid_action_error, e.what());
    } catch (const manyworlds::ConfigError& e) {
      PyErr_SetString(g_config_error, e.what());
    } catch (const manyworlds::TaskStateError& e) {
      PyErr_SetString(g_task_state_error, e.what());
    } catch (const manyworlds::EpisodeStateError& e) {
      PyErr_SetString(g_episode_state_error, e.what());
    } catch (const manyworlds::Error& e) {
      PyErr_SetString(g_error, e.what());
    } catch (const nlohmann::json::exception& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  EnsureOsmesaGlobal();
  BindEnv(m);
  BindExecutor(m);
  BindSawyerReward(m);
  BindBenchmarks(m);
}
