// Shared declarations of the manyworlds._core bindings.
#ifndef MANYWORLDS_PYTHON_BINDINGS_H_
#define MANYWORLDS_PYTHON_BINDINGS_H_

#include <memory>
#include <string>

#include <pybind11/pybind11.h>

#include "manyworlds/core/env.h"

namespace manyworlds::python {

namespace py = pybind11;

// One env made from the default registry, as Python sees it. The C++ env can
// be moved into a batched executor; the object is unusable afterwards.
struct PyEnv {
  std::string id;      // registry id
  std::string family;  // registry family: classic, manipulation, benchmark
  std::unique_ptr<Env> env;
  std::shared_ptr<void> renderer;  // sim::Renderer, made on the first render
  std::vector<uint8_t> pixels;     // the last pixel observation (empty without obs=pixels)

  Env& get();
  const Env& get() const;
};

// After a long call that released the GIL: raises KeyboardInterrupt (or any
// other signal handler's exception) at once instead of at the next bytecode.
void CheckSignals();

void BindEnv(py::module_& m);
void BindExecutor(py::module_& m);
void BindSawyerReward(py::module_& m);  // no-op without MuJoCo
void BindBenchmarks(py::module_& m);     // no-op without MuJoCo

}  // namespace manyworlds::python

#endif  // MANYWORLDS_PYTHON_BINDINGS_H_
