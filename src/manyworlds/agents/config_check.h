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

// The config once its Validate() passed: for a learner's initializer list,
// so no network is built from a bad config.
template <typename Config>
const Config& Validated(const Config& config) {
  config.Validate();
  return config;
}

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

// The advantage estimate of the on-policy learners: discount and gae_lambda
// in [0, 1].
inline void RequireDiscountAndLambda(double discount, double gae_lambda) {
  RequireField(discount >= 0 && discount <= 1, "discount", "in [0, 1]", discount);
  RequireField(gae_lambda >= 0 && gae_lambda <= 1, "gae_lambda", "in [0, 1]", gae_lambda);
}

// The entropy term of PPO-style learners: entropy_method one of regularized,
// max (a reward bonus), none; entropy_coeff finite and >= 0.
inline void RequireEntropyTerm(const std::string& entropy_method, double entropy_coeff) {
  RequireField(
      entropy_method == "regularized" || entropy_method == "max" || entropy_method == "none",
      "entropy_method", "one of regularized, max, none", entropy_method);
  RequireField(std::isfinite(entropy_coeff) && entropy_coeff >= 0, "entropy_coeff",
               "finite and >= 0", entropy_coeff);
}

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_CONFIG_CHECK_H_
