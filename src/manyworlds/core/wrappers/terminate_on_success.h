// TerminateOnSuccess: ends an episode (terminated = true) at the first step
// whose `success` info field is > 0.5, as Meta-World v3's
// AutoTerminateOnSuccessWrapper (on for its meta-test envs and forced by its
// evaluation functions). Any env with a `success` info field.
#ifndef MANYWORLDS_CORE_WRAPPERS_TERMINATE_ON_SUCCESS_H_
#define MANYWORLDS_CORE_WRAPPERS_TERMINATE_ON_SUCCESS_H_

#include <cstddef>
#include <memory>

#include "manyworlds/core/wrapper.h"

namespace manyworlds {

class TerminateOnSuccess : public Wrapper {
 public:
  // Throws ConfigError if the env reports no `success` info field.
  explicit TerminateOnSuccess(std::unique_ptr<Env> inner);

 protected:
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  size_t success_index_ = 0;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_TERMINATE_ON_SUCCESS_H_
