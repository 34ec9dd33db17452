// manyworlds._core.Env, the registry listing, Rng and mix_seed.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "convert.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"
#ifdef MANYWORLDS_PY_RENDER
#include "manyworlds/sim/render.h"
#endif

namespace manyworlds::python {

Env& PyEnv::get() {
  if (!env) throw EpisodeStateError("env '" + id + "' was moved into a vector env and is no longer usable");
  return *env;
}
const Env& PyEnv::get() const { return const_cast<PyEnv*>(this)->get(); }

void CheckSignals() {
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

namespace {

py::array_t<float> Floats(std::span<const float> values) {
  py::array_t<float> array(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), array.mutable_data());
  return array;
}

py::list RegistryEntries() {
  py::list list;
  for (const EnvRegistration& r : DefaultRegistry().entries()) {
    py::dict entry;
    entry["id"] = r.id;
    entry["family"] = r.family;
    entry["description"] = r.description;
    py::list options;
    for (const OptionSpec& o : r.options) {
      py::dict option;
      option["name"] = o.name;
      option["type"] = OptionTypeName(o.type);
      option["default"] = FromJson(o.default_value);
      option["doc"] = o.doc;
      option["choices"] = py::cast(o.choices);
      options.append(option);
    }
    entry["options"] = options;
    list.append(entry);
  }
  return list;
}

std::unique_ptr<PyEnv> MakeEnv(const std::string& id, const py::dict& options) {
  const nlohmann::json json = ToJson(options, "options of env '" + id + "'");
  auto out = std::make_unique<PyEnv>();
  out->id = id;
  out->family = DefaultRegistry().Find(id).family;
  out->env = DefaultRegistry().Make(id, json);
  return out;
}

py::tuple Reset(PyEnv& self) {
  Env& env = self.get();
  py::array_t<float> env_obs(env.spec().env_obs_space.flat_size());
  py::array_t<float> task_obs(env.spec().task_obs_space.flat_size());
  self.pixels.resize(env.spec().pixel_space.flat_size());
  ObsView view{{env_obs.mutable_data(), static_cast<size_t>(env_obs.size())},
               {task_obs.mutable_data(), static_cast<size_t>(task_obs.size())},
               self.pixels};
  {
    py::gil_scoped_release release;
    env.Reset(view);
  }
  CheckSignals();
  return py::make_tuple(env_obs, task_obs);
}

py::tuple Step(PyEnv& self, const py::handle& action) {
  Env& env = self.get();
  const EnvSpec& spec = env.spec();
  auto a = FloatArray(action, spec.action_space.flat_size(), ("action of env '" + self.id + "'").c_str());
  py::array_t<float> env_obs(spec.env_obs_space.flat_size());
  py::array_t<float> task_obs(spec.task_obs_space.flat_size());
  py::array_t<float> info(static_cast<py::ssize_t>(spec.info_fields.size()));
  float reward = 0.0f;
  bool terminated = false, truncated = false;
  self.pixels.resize(spec.pixel_space.flat_size());
  StepView view{{env_obs.mutable_data(), static_cast<size_t>(env_obs.size())},
                {task_obs.mutable_data(), static_cast<size_t>(task_obs.size())},
                &reward,
                &terminated,
                &truncated,
                {info.mutable_data(), static_cast<size_t>(info.size())},
                self.pixels};
  {
    py::gil_scoped_release release;
    env.Step({a.data(), static_cast<size_t>(a.size())}, view);
  }
  CheckSignals();
  return py::make_tuple(env_obs, task_obs, reward, terminated, truncated, info);
}

py::array_t<uint8_t> Render(PyEnv& self, const std::string& camera, int width, int height) {
#ifdef MANYWORLDS_PY_RENDER
  Env& env = self.get();
  const MujocoScene scene = ActiveMujocoScene(env);  // ConfigError for other envs
  auto renderer = std::static_pointer_cast<sim::Renderer>(self.renderer);
  if (!renderer || renderer->width() != width || renderer->height() != height) {
    renderer = std::make_shared<sim::Renderer>(width, height);
    self.renderer = renderer;
  }
  py::array_t<uint8_t> rgb({static_cast<py::ssize_t>(height), static_cast<py::ssize_t>(width),
                            py::ssize_t{3}});
  {
    py::gil_scoped_release release;
    renderer->Render(scene.model, scene.data, camera,
                     {rgb.mutable_data(), static_cast<size_t>(rgb.size())});
  }
  return rgb;
#else
  (void)camera, (void)width, (void)height;
  throw Error("env '" + self.id + "': this build of manyworlds has no renderer (OSMesa or MuJoCo missing)");
#endif
}

// An env's own policy (core/policy.h), for agents that drive Python envs the
// way PolicyActor drives the C++ protocols' envs.
struct PyPolicy {
  std::unique_ptr<Policy> policy;
  int64_t obs_size = 0;
  int64_t action_size = 0;
};

std::unique_ptr<PyPolicy> MakePyPolicy(PyEnv& env, std::unique_ptr<Policy> policy) {
  auto out = std::make_unique<PyPolicy>();
  out->policy = std::move(policy);
  out->obs_size = env.get().spec().env_obs_space.flat_size();
  out->action_size = env.get().spec().action_space.flat_size();
  return out;
}

}  // namespace

void BindEnv(py::module_& m) {
  m.def("registry_entries", &RegistryEntries,
        "Every registered env: list of dicts {id, family, description, options}; each option "
        "is {name, type, default, doc, choices}.");
  m.def("mix_seed", &MixSeed, py::arg("seed"), py::arg("index"),
        "Derives an independent seed from (seed, index) (SplitMix64 finaliser), as the "
        "executor and the command line do.");
  m.attr("has_mujoco") =
#ifdef MANYWORLDS_PY_MUJOCO
      true;
#else
      false;
#endif
  m.attr("has_render") =
#ifdef MANYWORLDS_PY_RENDER
      true;
#else
      false;
#endif

#ifdef MANYWORLDS_PY_RENDER
  m.attr("render_backend") = sim::RenderBackendName();
#else
  m.attr("render_backend") = "none (built without OSMesa)";
#endif

  py::class_<Rng>(m, "Rng", "manyworlds' portable random generator (xoshiro256**).")
      .def(py::init<uint64_t>(), py::arg("seed") = 0)
      .def("next_u64", &Rng::NextU64, "The next raw 64-bit value.")
      .def("uniform", py::overload_cast<>(&Rng::Uniform), "Uniform in [0, 1).");

  py::class_<PyEnv>(m, "Env", "One environment from the default registry (low-level; use manyworlds.make).")
      .def(py::init(&MakeEnv), py::arg("id"), py::arg("options") = py::dict(),
           "Makes env `id` with registry options (ValueError for an unknown id or option).")
      .def_property_readonly("id", [](const PyEnv& e) { return e.id; }, "Registry id.")
      .def_property_readonly("family", [](const PyEnv& e) { return e.family; },
                             "Registry family: classic, manipulation or benchmark.")
      .def_property_readonly("description", [](const PyEnv& e) { return e.get().spec().description; },
                             "One-line description from the registry.")
      .def_property_readonly("action_space", [](const PyEnv& e) { return SpaceToPython(e.get().spec().action_space); })
      .def_property_readonly("env_obs_space", [](const PyEnv& e) { return SpaceToPython(e.get().spec().env_obs_space); })
      .def_property_readonly("task_obs_space", [](const PyEnv& e) { return SpaceToPython(e.get().spec().task_obs_space); })
      .def_property_readonly("info_fields", [](const PyEnv& e) { return e.get().spec().info_fields; })
      .def_property_readonly("pixel_space", [](const PyEnv& e) { return SpaceToPython(e.get().spec().pixel_space); },
                             "Space of the pixel observation (shape (3 x frames, height, width), "
                             "uint8 values); shape (0,) without obs=pixels.")
      .def_property_readonly("pixels",
                             [](const PyEnv& e) {
                               const std::vector<int64_t>& shape = e.get().spec().pixel_space.shape();
                               py::array_t<uint8_t> out(std::vector<py::ssize_t>(shape.begin(), shape.end()));
                               std::copy(e.pixels.begin(), e.pixels.end(), out.mutable_data());
                               return out;
                             },
                             "The pixel observation of the last reset or step (a uint8 copy, "
                             "channels first); shape (0,) without obs=pixels.")
      .def_property_readonly("max_episode_steps", [](const PyEnv& e) { return e.get().spec().max_episode_steps; })
      .def_property_readonly("uses_env_seed", [](const PyEnv& e) { return e.get().spec().uses_env_seed; })
      .def_property_readonly("elapsed_steps", [](const PyEnv& e) { return e.get().elapsed_steps(); })
      .def_property_readonly("needs_reset", [](const PyEnv& e) { return e.get().needs_reset(); })
      .def_property_readonly("has_task", [](const PyEnv& e) { return e.get().has_task(); })
      .def_property_readonly("moved", [](const PyEnv& e) { return e.env == nullptr; },
                             "True once the env was moved into an executor.")
      .def("seed", [](PyEnv& e, uint64_t s) { e.get().Seed(s); }, py::arg("seed"),
           "Seeds dynamics and initial states; takes effect at the next reset.")
      .def("seed_task", [](PyEnv& e, uint64_t s) { e.get().SeedTask(s); }, py::arg("seed"),
           "Seeds the task sampler.")
      .def("sample_task_state", [](PyEnv& e) { return TaskStateToPython(e.get().SampleTaskState()); },
           "Draws a task state with the task generator (does not switch to it).")
      .def("get_task_state", [](const PyEnv& e) { return TaskStateToPython(e.get().GetTaskState()); },
           "The current task state (RuntimeError before a task was set or sampled).")
      .def("set_task_state",
           [](PyEnv& e, const py::handle& state) { e.get().SetTaskState(TaskStateFromPython(state)); },
           py::arg("state"), "Validates and switches to a task state; reset next.")
      .def("reset_task_state", [](PyEnv& e) { e.get().ResetTaskState(); },
           "Switches to a freshly sampled task; reset next.")
      .def("evaluation_tasks",
           [](const PyEnv& e) {
             py::list groups;
             for (const TaskGroup& g : e.get().EvaluationTasks()) {
               py::list states;
               for (const TaskState& s : g.states) states.append(TaskStateToPython(s));
               groups.append(py::make_tuple(g.name, states));
             }
             return groups;
           },
           "The fixed evaluation task states, in named groups: list of (name, [state]).")
      .def("set_max_episode_steps", [](PyEnv& e, int64_t n) { e.get().SetMaxEpisodeSteps(n); },
           py::arg("max_episode_steps"), "Changes the episode limit (0: none); reset next.")
      .def("reset", &Reset, "Starts an episode: (env_obs, task_obs) as float32 arrays.")
      .def("step", &Step, py::arg("action"),
           "One step: (env_obs, task_obs, reward, terminated, truncated, info_values).")
      .def("sample_action",
           [](PyEnv& e, Rng& rng) { return Floats(e.get().spec().action_space.Sample(rng)); },
           py::arg("rng"), "A uniformly random action drawn with `rng`, as a flat float32 array.")
      .def("render", &Render, py::arg("camera") = "front", py::arg("width") = 640,
           py::arg("height") = 480,
           "Renders the current MuJoCo scene offscreen: uint8 array (height, width, 3).");

  py::class_<PyPolicy>(m, "Policy",
                       "An env's own policy: its scripted (expert) policy or uniform random "
                       "actions (scripted_policy, random_policy).")
      .def("begin_episode", [](PyPolicy& p) { p.policy->BeginEpisode(); },
           "Call at the start of every episode.")
      .def(
          "act",
          [](PyPolicy& p, const py::handle& env_obs) {
            auto obs = FloatArray(env_obs, p.obs_size, "env_obs of a policy");
            py::array_t<float> action(p.action_size);
            p.policy->Act({obs.data(), static_cast<size_t>(obs.size())}, {},
                          {action.mutable_data(), static_cast<size_t>(action.size())});
            return action;
          },
          py::arg("env_obs"), "The action (float32, the env's units) for an env observation.");
  m.def(
      "scripted_policy",
      [](PyEnv& env) { return MakePyPolicy(env, MakeScriptedPolicy(env.get())); },
      py::arg("env"), py::keep_alive<0, 1>(),
      "The env's scripted policy (the manipulation tasks and benchmarks, the box world; "
      "ValueError for other envs). It reads the env's task, so it acts for this env only.");
  m.def(
      "random_policy",
      [](PyEnv& env, uint64_t seed) {
        return MakePyPolicy(env, std::make_unique<RandomPolicy>(env.get().spec().action_space, seed));
      },
      py::arg("env"), py::arg("seed"),
      "Uniform random actions from the env's action space, from a stream of `seed` (the same "
      "draws as the C++ protocols' random policy with that seed).");
}

}  // namespace manyworlds::python
