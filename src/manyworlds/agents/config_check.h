// Field checks shared by the agents' config validators, with one message:
// "'agent.FIELD' must be ALLOWED, got VALUE" (a ConfigError, exit code 2).
#ifndef MANYWORLDS_AGENTS_CONFIG_CHECK_H_
#define MANYWORLDS_AGENTS_CONFIG_CHECK_H_

#include <cmath>
#include <sstream>

#include "manyworlds/core/error.h"

namespace manyworlds::agents {

template <typename T>
void RequireField(bool ok, const char* field, const char* allowed, const T& value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "'agent." << field << "' must be " << allowed << ", got " << value;
  throw ConfigError(msg.str());
}

inline bool FinitePositive(double x) { return std::isfinite(x) && x > 0; }

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_CONFIG_CHECK_H_
