// Field checks shared by the agents' config validators, with one message:
// "'agent.FIELD' must be ALLOWED, got VALUE" (a ConfigError, exit code 2).
#ifndef MANYWORLDS_AGENTS_CONFIG_CHECK_H_
#define MANYWORLDS_AGENTS_CONFIG_CHECK_H_

#include <cmath>
#include <sstream>
#include <string>
#include <string_view>

#include "manyworlds/core/error.h"

namespace manyworlds::agents {

template <typename T>
void RequireField(bool ok, std::string_view field, std::string_view allowed, const T& value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "'agent." << field << "' must be " << allowed << ", got " << value;
  throw ConfigError(msg.str());
}

inline bool FinitePositive(double x) { return std::isfinite(x) && x > 0; }

// The std bounds of a Gaussian policy or encoder (fields PREFIX + min_std,
// max_std, init_std): 0 < min_std <= init_std <= max_std < inf.
inline void RequireStdBounds(const std::string& prefix, double min_std, double max_std,
                             double init_std) {
  const std::string min = prefix + "min_std", max = prefix + "max_std";
  RequireField(FinitePositive(min_std), min, "finite and > 0", min_std);
  RequireField(FinitePositive(max_std) && max_std >= min_std, max, "finite and >= " + min, max_std);
  RequireField(init_std >= min_std && init_std <= max_std, prefix + "init_std",
               "in [" + min + ", " + max + "]", init_std);
}

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_CONFIG_CHECK_H_
