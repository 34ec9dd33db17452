// manyworlds._core.sawyer_reward: a manipulation task's reward, success and
// info evaluated on a state record given from Python (e.g. quantities read
// from Meta-World's own simulator), for the fidelity tests.
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.h"
#include "manyworlds/core/error.h"

#ifdef MANYWORLDS_PY_MUJOCO
#include "manyworlds/manipulation/sawyer_task.h"
#endif

namespace manyworlds::python {
namespace {

#ifdef MANYWORLDS_PY_MUJOCO
using manipulation::SawyerState;
using manipulation::SawyerTask;

manipulation::Vec3 ReadVec3(const py::dict& record, const char* key) {
  const auto values = record[key].cast<std::vector<double>>();
  if (values.size() != 3) {
    throw ConfigError(std::string("sawyer_reward: '") + key + "' must have 3 values, got " +
                      std::to_string(values.size()));
  }
  return {values[0], values[1], values[2]};
}

std::array<double, 4> ReadVec4(const py::dict& record, const char* key) {
  const auto values = record[key].cast<std::vector<double>>();
  if (values.size() != 4) {
    throw ConfigError(std::string("sawyer_reward: '") + key + "' must have 4 values, got " +
                      std::to_string(values.size()));
  }
  return {values[0], values[1], values[2], values[3]};
}

SawyerState ReadRecord(const py::dict& record) {
  const std::set<std::string> known(std::begin(manipulation::kSawyerStateFields),
                                    std::end(manipulation::kSawyerStateFields));
  std::string all;
  for (const char* name : manipulation::kSawyerStateFields) all += (all.empty() ? "" : ", ") + std::string(name);
  for (const auto& item : record) {
    const std::string key = py::str(item.first);
    if (known.count(key) == 0) {
      throw ConfigError("sawyer_reward: unknown field '" + key + "'; the fields are: " + all);
    }
  }
  for (const char* name : manipulation::kSawyerStateFields) {
    if (!record.contains(name)) {
      throw ConfigError(std::string("sawyer_reward: missing field '") + name + "'; the fields are: " + all);
    }
  }
  SawyerState s;
  s.hand = ReadVec3(record, "hand");
  s.tcp = ReadVec3(record, "tcp");
  s.left_pad = ReadVec3(record, "left_pad");
  s.right_pad = ReadVec3(record, "right_pad");
  s.obj = ReadVec3(record, "obj");
  s.goal = ReadVec3(record, "goal");
  s.obj_init = ReadVec3(record, "obj_init");
  s.tcp_init = ReadVec3(record, "tcp_init");
  s.hand_init = ReadVec3(record, "hand_init");
  s.gripper_opening = record["gripper_opening"].cast<double>();
  s.touching_obj = record["touching_obj"].cast<bool>();
  s.obj_head = ReadVec3(record, "obj_head");
  s.obj_head_init = ReadVec3(record, "obj_head_init");
  s.joint_qpos = record["joint_qpos"].cast<double>();
  s.handle_init = ReadVec3(record, "handle_init");
  s.obj_to_target_init = record["obj_to_target_init"].cast<double>();
  s.obj_quat = ReadVec4(record, "obj_quat");
  s.obj2 = ReadVec3(record, "obj2");
  s.obj2_init = ReadVec3(record, "obj2_init");
  s.v1_max_dist = record["v1_max_dist"].cast<double>();
  s.v1_obj_height = record["v1_obj_height"].cast<double>();
  s.v1_height_target = record["v1_height_target"].cast<double>();
  s.left_finger = ReadVec3(record, "left_finger");
  s.v1_max_dist2 = record["v1_max_dist2"].cast<double>();
  s.obj2_head = ReadVec3(record, "obj2_head");
  return s;
}

py::dict SawyerReward(PyEnv& env, const py::dict& record,
                      const py::array_t<float, py::array::c_style | py::array::forcecast>& action) {
  const auto* task = dynamic_cast<const SawyerTask*>(&env.get());
  if (task == nullptr) {
    throw ConfigError("sawyer_reward: env '" + env.id +
                      "' is not a manipulation task made without wrappers (make it with no "
                      "terminate_on_success or recurrent_meta_obs option)");
  }
  const manipulation::RewardTerms t =
      task->EvaluateReward(ReadRecord(record), {action.data(), static_cast<size_t>(action.size())});
  py::dict out;
  out["reward"] = t.reward;
  out["success"] = t.success ? 1.0 : 0.0;
  out["near_object"] = t.near_object;
  out["grasp_success"] = t.grasp_success;
  out["grasp_reward"] = t.grasp_reward;
  out["in_place_reward"] = t.in_place_reward;
  out["obj_to_target"] = t.obj_to_target;
  out["unscaled_reward"] = t.reward;
  return out;
}

py::dict SawyerStateOf(PyEnv& env) {
  const auto* task = dynamic_cast<const SawyerTask*>(&env.get());
  if (task == nullptr) throw ConfigError("sawyer_state: env '" + env.id + "' is not a manipulation task");
  const SawyerState& s = task->state();
  py::dict out;
  auto vec = [](const manipulation::Vec3& v) { return std::vector<double>(v.begin(), v.end()); };
  out["hand"] = vec(s.hand);
  out["tcp"] = vec(s.tcp);
  out["left_pad"] = vec(s.left_pad);
  out["right_pad"] = vec(s.right_pad);
  out["obj"] = vec(s.obj);
  out["goal"] = vec(s.goal);
  out["obj_init"] = vec(s.obj_init);
  out["tcp_init"] = vec(s.tcp_init);
  out["hand_init"] = vec(s.hand_init);
  out["gripper_opening"] = s.gripper_opening;
  out["touching_obj"] = s.touching_obj;
  out["obj_head"] = vec(s.obj_head);
  out["obj_head_init"] = vec(s.obj_head_init);
  out["joint_qpos"] = s.joint_qpos;
  out["handle_init"] = vec(s.handle_init);
  out["obj_to_target_init"] = s.obj_to_target_init;
  out["obj_quat"] = std::vector<double>(s.obj_quat.begin(), s.obj_quat.end());
  out["obj2"] = vec(s.obj2);
  out["obj2_init"] = vec(s.obj2_init);
  out["v1_max_dist"] = s.v1_max_dist;
  out["v1_obj_height"] = s.v1_obj_height;
  out["v1_height_target"] = s.v1_height_target;
  out["left_finger"] = vec(s.left_finger);
  out["v1_max_dist2"] = s.v1_max_dist2;
  out["obj2_head"] = vec(s.obj2_head);
  return out;
}
#endif

}  // namespace

void BindSawyerReward(py::module_& m) {
#ifdef MANYWORLDS_PY_MUJOCO
  std::vector<std::string> fields(std::begin(manipulation::kSawyerStateFields),
                                  std::end(manipulation::kSawyerStateFields));
  m.attr("sawyer_state_fields") = fields;
  m.def("sawyer_reward", &SawyerReward, py::arg("env"), py::arg("state"), py::arg("action"),
        "Reward, success and info of manipulation env `env` (an Env made with no wrapper "
        "options) for a state record (dict with the keys in sawyer_state_fields: 3-vectors and "
        "gripper_opening, touching_obj) and a 4-value action; a dict of floats keyed like the "
        "step's info, plus 'reward'.");
  m.def("sawyer_state", &SawyerStateOf, py::arg("env"),
        "The state record of manipulation env `env` after its last reset or step.");
#else
  (void)m;
#endif
}

}  // namespace manyworlds::python
