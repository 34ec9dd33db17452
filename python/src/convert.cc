#include "convert.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace manyworlds::python {
namespace {

[[noreturn]] void Fail(const std::string& where, const std::string& path, const std::string& what) {
  std::string field = path.empty() ? where : where + " field '" + path + "'";
  throw py::value_error(field + ": " + what);
}

std::string TypeName(const py::handle& value) {
  return py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>();
}

nlohmann::json ToJsonAt(const py::handle& value, const std::string& where, const std::string& path,
                        int depth) {
  if (depth > 64) Fail(where, path, "nested too deeply");
  if (value.is_none()) return nullptr;
  if (PyBool_Check(value.ptr())) return value.cast<bool>();
  if (PyLong_Check(value.ptr())) {
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (overflow == 0) return static_cast<int64_t>(v);
    if (overflow > 0) {
      const unsigned long long u = PyLong_AsUnsignedLongLong(value.ptr());
      if (!PyErr_Occurred()) return static_cast<uint64_t>(u);
      PyErr_Clear();
    }
    Fail(where, path, "integer out of the 64-bit range");
  }
  if (PyFloat_Check(value.ptr())) return PyFloat_AsDouble(value.ptr());
  if (PyUnicode_Check(value.ptr())) return value.cast<std::string>();
  if (PyDict_Check(value.ptr())) {
    nlohmann::json object = nlohmann::json::object();
    for (auto item : py::reinterpret_borrow<py::dict>(value)) {
      if (!PyUnicode_Check(item.first.ptr())) {
        Fail(where, path, "dict keys must be strings, got " + TypeName(item.first));
      }
      const std::string key = item.first.cast<std::string>();
      object[key] = ToJsonAt(item.second, where, path.empty() ? key : path + "." + key, depth + 1);
    }
    return object;
  }
  if (PyList_Check(value.ptr()) || PyTuple_Check(value.ptr())) {
    nlohmann::json array = nlohmann::json::array();
    size_t i = 0;
    for (auto item : py::reinterpret_borrow<py::sequence>(value)) {
      array.push_back(ToJsonAt(item, where, path + "[" + std::to_string(i) + "]", depth + 1));
      ++i;
    }
    return array;
  }
  // numpy scalars and arrays: through their Python equivalents.
  if (py::hasattr(value, "dtype")) {
    if (py::hasattr(value, "tolist") && py::hasattr(value, "ndim")) {
      return ToJsonAt(value.attr("tolist")(), where, path, depth + 1);
    }
  }
  Fail(where, path, "unsupported type " + TypeName(value) +
                        " (use dict, list, str, int, float, bool or None)");
}

}  // namespace

nlohmann::json ToJson(const py::handle& value, const std::string& where) {
  return ToJsonAt(value, where, "", 0);
}

py::object FromJson(const nlohmann::json& json) {
  switch (json.type()) {
    case nlohmann::json::value_t::null:
      return py::none();
    case nlohmann::json::value_t::boolean:
      return py::bool_(json.get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(json.get<int64_t>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(json.get<uint64_t>());
    case nlohmann::json::value_t::number_float:
      return py::float_(json.get<double>());
    case nlohmann::json::value_t::string:
      return py::str(json.get_ref<const std::string&>());
    case nlohmann::json::value_t::array: {
      py::list list;
      for (const auto& item : json) list.append(FromJson(item));
      return list;
    }
    case nlohmann::json::value_t::object: {
      py::dict dict;
      for (const auto& [key, item] : json.items()) dict[py::str(key)] = FromJson(item);
      return dict;
    }
    default:
      throw py::value_error("JSON value of an unsupported type (binary)");
  }
}

TaskState TaskStateFromPython(const py::handle& value) {
  if (!PyDict_Check(value.ptr())) {
    throw py::value_error("task state: expected a dict {'env': str, 'params': dict}, got " +
                          TypeName(value));
  }
  const auto dict = py::reinterpret_borrow<py::dict>(value);
  for (auto item : dict) {
    const std::string key = py::str(item.first).cast<std::string>();
    if (key != "env" && key != "params") {
      throw py::value_error("task state: unknown field '" + key +
                            "' (a task state has exactly 'env' and 'params')");
    }
  }
  if (!dict.contains("env")) throw py::value_error("task state: missing field 'env'");
  if (!dict.contains("params")) throw py::value_error("task state: missing field 'params'");
  py::handle env = dict["env"];
  py::handle params = dict["params"];
  if (!PyUnicode_Check(env.ptr())) {
    throw py::value_error("task state field 'env': expected a string, got " + TypeName(env));
  }
  if (!PyDict_Check(params.ptr())) {
    throw py::value_error("task state field 'params': expected a dict, got " + TypeName(params));
  }
  TaskState state;
  state.env = env.cast<std::string>();
  state.params = ToJsonAt(params, "task state", "params", 0);
  return state;
}

py::dict TaskStateToPython(const TaskState& state) {
  py::dict dict;
  dict["env"] = py::str(state.env);
  dict["params"] = FromJson(state.params);
  return dict;
}

py::dict SpaceToPython(const Space& space) {
  py::dict dict;
  if (space.is_discrete()) {
    dict["kind"] = "discrete";
    dict["n"] = space.n();
    return dict;
  }
  std::vector<py::ssize_t> shape(space.shape().begin(), space.shape().end());
  py::array_t<float> low(shape), high(shape);
  std::copy(space.low().begin(), space.low().end(), low.mutable_data());
  std::copy(space.high().begin(), space.high().end(), high.mutable_data());
  dict["kind"] = "box";
  dict["low"] = low;
  dict["high"] = high;
  py::tuple shape_tuple(shape.size());
  for (size_t i = 0; i < shape.size(); ++i) shape_tuple[i] = py::int_(shape[i]);
  dict["shape"] = shape_tuple;
  return dict;
}

py::array_t<float, py::array::c_style> FloatArray(const py::handle& value, py::ssize_t size,
                                                   const char* what) {
  auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!array) {
    PyErr_Clear();
    throw py::value_error(std::string(what) + ": expected an array of numbers, got " +
                          TypeName(value));
  }
  if (array.size() != size) {
    throw py::value_error(std::string(what) + ": expected " + std::to_string(size) +
                          " values, got " + std::to_string(array.size()));
  }
  return array;
}

}  // namespace manyworlds::python
