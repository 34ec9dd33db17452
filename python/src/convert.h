// Conversions between Python objects and the C++ types the bindings pass:
// JSON values (task states, registry options), spaces, and numpy arrays.
#ifndef MANYWORLDS_PYTHON_CONVERT_H_
#define MANYWORLDS_PYTHON_CONVERT_H_

#include <string>

#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "manyworlds/core/space.h"
#include "manyworlds/core/task_state.h"

namespace manyworlds::python {

namespace py = pybind11;

// A Python value (dict with str keys, list/tuple, str, bool, int, float,
// None, numpy scalars and arrays) as JSON. Anything else raises ValueError
// naming `where` and the path inside the value, e.g. "task state field
// 'params.goal_pos[1]'".
nlohmann::json ToJson(const py::handle& value, const std::string& where);
// JSON as plain Python values (dict, list, str, bool, int, float, None).
py::object FromJson(const nlohmann::json& json);

// A task state dict {"env": str, "params": dict}; ValueError naming the
// field when it has another shape.
TaskState TaskStateFromPython(const py::handle& value);
py::dict TaskStateToPython(const TaskState& state);

// {"kind": "box", "low": ndarray, "high": ndarray, "shape": tuple} or
// {"kind": "discrete", "n": int}.
py::dict SpaceToPython(const Space& space);

// A float32 C-contiguous array of `size` elements from any array-like
// (copied only when the dtype or layout differ). ValueError otherwise.
py::array_t<float, py::array::c_style> FloatArray(const py::handle& value, py::ssize_t size,
                                                   const char* what);

}  // namespace manyworlds::python

#endif  // MANYWORLDS_PYTHON_CONVERT_H_
