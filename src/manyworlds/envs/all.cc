#include "manyworlds/envs/all.h"

#include "manyworlds/classic/classic.h"

namespace manyworlds {

const Registry& DefaultRegistry() {
  // a function-local static is initialised exactly once, even under races
  static const Registry registry = [] {
    Registry r;
    RegisterClassicSuite(r);
    // ---- MANIPULATION SUITE: the lead adds RegisterManipulationSuite(r) here
    // (and manyworlds::manipulation to PUBLIC_DEPS in CMakeLists.txt). ----
    return r;
  }();
  return registry;
}

std::unique_ptr<Env> Make(std::string_view id, const nlohmann::json& options) {
  return DefaultRegistry().Make(id, options);
}

}  // namespace manyworlds
