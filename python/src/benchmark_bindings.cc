// manyworlds._core.benchmark_splits: the published benchmarks' task lists
// (Meta-World v3's memberships and order), for manyworlds.benchmarks.
#include <map>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.h"

#ifdef MANYWORLDS_PY_MUJOCO
#include "manyworlds/manipulation/benchmark.h"
#endif

namespace manyworlds::python {

void BindBenchmarks(py::module_& m) {
#ifdef MANYWORLDS_PY_MUJOCO
  m.def(
      "benchmark_splits",
      [] {
        std::map<std::string, std::map<std::string, std::vector<std::string>>> out;
        for (const auto& b : manipulation::PublishedBenchmarks()) {
          out[b.id]["train"] = b.train;
          out[b.id]["test"] = b.test;
        }
        return out;
      },
      "{benchmark id: {'train': [task ids], 'test': [task ids]}} for mt10, mt25, mt50, ml10, "
      "ml25 and ml45, in Meta-World v3's order (a task's position is its one-hot index).");
#else
  (void)m;
#endif
}

}  // namespace manyworlds::python
