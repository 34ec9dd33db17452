// manyworlds._core.Executor: the batched executor with its buffers exposed as
// numpy views (no copies). A view keeps the executor alive; the buffers are
// rewritten by every reset/step/recv, so a caller that keeps values copies.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "convert.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/executor.h"
#include "manyworlds/core/limits.h"
#include "manyworlds/core/memory.h"

namespace manyworlds::python {
namespace {

struct PyExecutor {
  std::vector<std::string> ids;
  std::unique_ptr<BatchedExecutor> exec;
  bool pending = false;

  BatchedExecutor& get() {
    if (!exec) throw EpisodeStateError("vector env is closed");
    return *exec;
  }
};

std::unique_ptr<PyExecutor> MakeExecutor(py::list envs, int num_threads, bool auto_reset) {
  std::vector<PyEnv*> sources;
  for (auto item : envs) {
    if (!py::isinstance<PyEnv>(item)) {
      throw py::value_error("Executor: expected a list of manyworlds._core.Env, got an item of type " +
                            py::str(py::type::handle_of(item).attr("__name__")).cast<std::string>());
    }
    PyEnv* env = item.cast<PyEnv*>();
    env->get();  // raises if already moved
    for (PyEnv* other : sources) {
      if (other == env) throw py::value_error("Executor: the same env object appears twice");
    }
    sources.push_back(env);
  }
  auto out = std::make_unique<PyExecutor>();
  std::vector<std::unique_ptr<Env>> owned;
  for (PyEnv* env : sources) {
    out->ids.push_back(env->id);
    owned.push_back(std::move(env->env));
  }
  try {
    out->exec = std::make_unique<BatchedExecutor>(
        std::move(owned), ExecutorOptions{.num_threads = num_threads, .auto_reset = auto_reset});
  } catch (...) {
    // The executor took the envs by value; nothing to give back. The Python
    // objects stay moved-from, which get() reports clearly.
    throw;
  }
  return out;
}

// A read-only numpy view of executor memory; `owner` (the Python executor)
// stays alive as long as the view does.
template <typename T>
py::array View(py::handle owner, const T* data, std::vector<py::ssize_t> shape) {
  py::array array(py::dtype::of<T>(), shape, data, owner);
  py::detail::array_proxy(array.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return array;
}

py::array_t<float, py::array::c_style> Actions(PyExecutor& self, const py::handle& actions) {
  BatchedExecutor& exec = self.get();
  return FloatArray(actions, static_cast<py::ssize_t>(exec.num_envs()) * exec.action_size(),
                    "actions of the vector env");
}

}  // namespace

void BindExecutor(py::module_& m) {
  // the bounds every entry point shares (core/limits.h)
  m.attr("MAX_ENVS") = kMaxEnvs;
  m.attr("MAX_THREADS") = kMaxThreads;
  py::class_<BatchMemoryCheck>(m, "BatchMemoryCheck",
                               "Refuses a batch of `count` items (envs) that cannot fit in "
                               "memory, projected from the first items made (core/memory.h).")
      .def(py::init<int64_t, std::string, std::string>(), py::arg("count"), py::arg("what"),
           py::arg("hint"))
      .def("made", &BatchMemoryCheck::Made, py::arg("index"),
           "Call after item `index`; raises ValueError when the batch cannot fit.");
  py::class_<PyExecutor>(m, "Executor",
                         "The batched executor: N envs stepped on T threads into contiguous "
                         "buffers exposed as numpy views (low-level; use manyworlds.make_vec).")
      .def(py::init(&MakeExecutor), py::arg("envs"), py::arg("num_threads") = 1,
           py::arg("auto_reset") = true,
           "Takes the C++ envs out of `envs` (those objects become unusable). ValueError if "
           "their sizes or info fields differ.")
      .def_property_readonly("ids", [](const PyExecutor& e) { return e.ids; })
      .def_property_readonly("num_envs", [](PyExecutor& e) { return e.get().num_envs(); })
      .def_property_readonly("num_threads", [](PyExecutor& e) { return e.get().num_threads(); })
      .def_property_readonly("action_size", [](PyExecutor& e) { return e.get().action_size(); })
      .def_property_readonly("env_obs_size", [](PyExecutor& e) { return e.get().env_obs_size(); })
      .def_property_readonly("task_obs_size", [](PyExecutor& e) { return e.get().task_obs_size(); })
      .def_property_readonly("info_fields", [](PyExecutor& e) { return e.get().info_fields(); })
      .def_property_readonly("pending", [](const PyExecutor& e) { return e.pending; },
                             "True between send() and recv().")
      .def_property_readonly("closed", [](const PyExecutor& e) { return e.exec == nullptr; })
      .def("action_space", [](PyExecutor& e, int i) { return SpaceToPython(e.get().env(i).spec().action_space); }, py::arg("index") = 0,
           "Action space of env `index`.")
      .def("env_obs_space", [](PyExecutor& e, int i) { return SpaceToPython(e.get().env(i).spec().env_obs_space); }, py::arg("index") = 0,
           "Env-observation space of env `index`.")
      .def("task_obs_space", [](PyExecutor& e, int i) { return SpaceToPython(e.get().env(i).spec().task_obs_space); }, py::arg("index") = 0,
           "Task-observation space of env `index`.")
      .def("max_episode_steps", [](PyExecutor& e, int i) { return e.get().env(i).spec().max_episode_steps; }, py::arg("index") = 0,
           "Episode limit of env `index` (0: none).")
      .def("seed", [](PyExecutor& e, uint64_t s, uint64_t t) { e.get().Seed(s, t); },
           py::arg("env_seed"), py::arg("task_seed"),
           "Env i gets seed(mix_seed(env_seed, i)) and seed_task(mix_seed(task_seed, i)).")
      .def("seed_env", [](PyExecutor& e, int i, uint64_t s) { e.get().env(i).Seed(s); },
           py::arg("index"), py::arg("seed"), "Seeds env `index` (dynamics, initial states).")
      .def("seed_task_env", [](PyExecutor& e, int i, uint64_t s) { e.get().env(i).SeedTask(s); },
           py::arg("index"), py::arg("seed"), "Seeds the task sampler of env `index`.")
      .def("sample_task_state", [](PyExecutor& e, int i) { return TaskStateToPython(e.get().env(i).SampleTaskState()); },
           py::arg("index"), "Draws a task state from env `index`'s task sampler.")
      .def("get_task_state", [](PyExecutor& e, int i) { return TaskStateToPython(e.get().env(i).GetTaskState()); },
           py::arg("index"), "The current task state of env `index`.")
      .def("set_task_state",
           [](PyExecutor& e, int i, const py::handle& state, bool reset) {
             if (e.pending) throw EpisodeStateError("vector env: set_task_state between send() and recv()");
             const TaskState parsed = TaskStateFromPython(state);
             if (reset) {
               e.get().SetTaskState(i, parsed);
             } else {
               e.get().env(i).SetTaskState(parsed);
             }
           },
           py::arg("index"), py::arg("state"), py::arg("reset") = true,
           "Switches env `index` to a task; with reset (default) it is reset at once and its "
           "observation rows change, otherwise the next reset() starts it.")
      .def("reset_task_state",
           [](PyExecutor& e, int i) {
             if (e.pending) throw EpisodeStateError("vector env: reset_task_state between send() and recv()");
             BatchedExecutor& exec = e.get();
             exec.SetTaskState(i, exec.env(i).SampleTaskState());
           },
           py::arg("index"), "Switches env `index` to a freshly sampled task and resets it.")
      .def("switch_task",
           [](PyExecutor& e, int i) {
             if (e.pending) throw EpisodeStateError("vector env: switch_task between send() and recv()");
             Env& env = e.get().env(i);
             env.SetTaskState(env.SampleTaskState());
           },
           py::arg("index"),
           "Switches env `index` to a freshly sampled task without resetting it; the next reset() "
           "starts it.")
      .def("reset",
           [](PyExecutor& e) {
             BatchedExecutor& exec = e.get();
             {
               py::gil_scoped_release release;
               exec.Reset();
             }
             CheckSignals();
           },
           "Resets every env (fills env_obs / task_obs).")
      .def("step",
           [](PyExecutor& e, const py::handle& actions) {
             auto a = Actions(e, actions);
             BatchedExecutor& exec = e.get();
             {
               py::gil_scoped_release release;
               exec.Step({a.data(), static_cast<size_t>(a.size())});
             }
             CheckSignals();
           },
           py::arg("actions"), "Steps every env with its row of `actions` (num_envs x action_size).")
      .def("send",
           [](PyExecutor& e, const py::handle& actions) {
             auto a = Actions(e, actions);
             e.get().Send({a.data(), static_cast<size_t>(a.size())});  // copies the actions
             e.pending = true;
           },
           py::arg("actions"), "Starts a step on the worker threads and returns at once.")
      .def("recv",
           [](PyExecutor& e) {
             BatchedExecutor& exec = e.get();
             e.pending = false;
             {
               py::gil_scoped_release release;
               exec.Recv();
             }
             CheckSignals();
           },
           "Waits for the step started by send().")
      .def("close",
           [](PyExecutor& e) {
             // Buffers may still be viewed by numpy arrays, which hold a
             // reference to this object: the memory stays until they are gone.
             if (e.exec && e.pending) {
               py::gil_scoped_release release;
               e.exec->Recv();
             }
             e.pending = false;
           },
           "Finishes a pending step. The buffers are freed with the last reference.")
      .def_property_readonly("env_obs", [](py::object self) {
             auto& e = self.cast<PyExecutor&>().get();
             return View(self, e.env_obs().data(), {e.num_envs(), e.env_obs_size()});
           }, "(num_envs, env_obs_size) float32 view.")
      .def_property_readonly("task_obs", [](py::object self) {
             auto& e = self.cast<PyExecutor&>().get();
             return View(self, e.task_obs().data(), {e.num_envs(), e.task_obs_size()});
           }, "(num_envs, task_obs_size) float32 view.")
      .def_property_readonly("final_env_obs", [](py::object self) {
             auto& e = self.cast<PyExecutor&>().get();
             return View(self, e.final_env_obs().data(), {e.num_envs(), e.env_obs_size()});
           }, "(num_envs, env_obs_size) float32 view: last observation of the envs whose episode just ended.")
      .def_property_readonly("final_task_obs", [](py::object self) {
             auto& e = self.cast<PyExecutor&>().get();
             return View(self, e.final_task_obs().data(), {e.num_envs(), e.task_obs_size()});
           }, "(num_envs, task_obs_size) float32 view: task observation of the envs whose episode just ended.")
      .def_property_readonly("rewards", [](py::object self) {
             auto& e = self.cast<PyExecutor&>().get();
             return View(self, e.rewards().data(), {e.num_envs()});
           }, "(num_envs,) float32 view.")
      .def_property_readonly("terminated", [](py::object self) {
             auto& e = self.cast<PyExecutor&>().get();
             return View(self, e.terminated().data(), {e.num_envs()});
           }, "(num_envs,) bool view.")
      .def_property_readonly("truncated", [](py::object self) {
             auto& e = self.cast<PyExecutor&>().get();
             return View(self, e.truncated().data(), {e.num_envs()});
           }, "(num_envs,) bool view.")
      .def_property_readonly("info", [](py::object self) {
             auto& e = self.cast<PyExecutor&>().get();
             return View(self, e.info().data(),
                         {e.num_envs(), static_cast<py::ssize_t>(e.info_fields().size())});
           }, "(num_envs, len(info_fields)) float32 view.")
      .def_property_readonly("pixels", [](py::object self) {
             auto& exec = self.cast<PyExecutor&>().get();
             std::vector<py::ssize_t> shape{exec.num_envs()};
             for (int64_t d : exec.env(0).spec().pixel_space.shape()) shape.push_back(d);
             return View(self, exec.pixels().data(), shape);
           }, "(num_envs, 3 x frames, height, width) uint8 view of the pixel observations; "
              "(num_envs, 0) without obs=pixels.")
      .def_property_readonly("final_pixels", [](py::object self) {
             auto& exec = self.cast<PyExecutor&>().get();
             std::vector<py::ssize_t> shape{exec.num_envs()};
             for (int64_t d : exec.env(0).spec().pixel_space.shape()) shape.push_back(d);
             return View(self, exec.final_pixels().data(), shape);
           }, "As pixels: the last pixel observation of the envs whose episode just ended.")
      .def("pixel_space", [](PyExecutor& e, int i) { return SpaceToPython(e.get().env(i).spec().pixel_space); }, py::arg("index") = 0,
           "Pixel-observation space of env `index` (shape (0,) without obs=pixels).")
      .def_property_readonly("episode_steps", [](py::object self) {
             auto& e = self.cast<PyExecutor&>().get();
             return View(self, e.episode_steps().data(), {e.num_envs()});
           }, "(num_envs,) int64 view: steps into the current episode.")
      .def("buffer_addresses",
           [](PyExecutor& e) {
             BatchedExecutor& exec = e.get();
             py::dict d;
             d["env_obs"] = reinterpret_cast<uintptr_t>(exec.env_obs().data());
             d["task_obs"] = reinterpret_cast<uintptr_t>(exec.task_obs().data());
             d["rewards"] = reinterpret_cast<uintptr_t>(exec.rewards().data());
             d["terminated"] = reinterpret_cast<uintptr_t>(exec.terminated().data());
             d["truncated"] = reinterpret_cast<uintptr_t>(exec.truncated().data());
             d["info"] = reinterpret_cast<uintptr_t>(exec.info().data());
             d["final_env_obs"] = reinterpret_cast<uintptr_t>(exec.final_env_obs().data());
             d["final_task_obs"] = reinterpret_cast<uintptr_t>(exec.final_task_obs().data());
             d["pixels"] = reinterpret_cast<uintptr_t>(exec.pixels().data());
             return d;
           },
           "Addresses of the C++ buffers, to check that the numpy views share them.");
}

}  // namespace manyworlds::python
