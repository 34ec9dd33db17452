#include "manyworlds/core/wrappers/terminate_on_success.h"

#include <algorithm>
#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/core/success.h"

namespace manyworlds {
namespace {

std::unique_ptr<Env> CheckSuccessField(std::unique_ptr<Env> inner) {
  if (!inner) return inner;  // Wrapper reports the null env
  const auto& fields = inner->spec().info_fields;
  if (std::find(fields.begin(), fields.end(), "success") == fields.end()) {
    throw ConfigError("wrapper terminate-on-success on env '" + inner->spec().id +
                      "': the env has no 'success' info field");
  }
  return inner;
}

}  // namespace

TerminateOnSuccess::TerminateOnSuccess(std::unique_ptr<Env> inner)
    : Wrapper(CheckSuccessField(std::move(inner)), "terminate-on-success") {
  const auto& fields = this->inner().spec().info_fields;
  success_index_ =
      static_cast<size_t>(std::find(fields.begin(), fields.end(), "success") - fields.begin());
}

void TerminateOnSuccess::DoStep(std::span<const float> action, const StepView& out) {
  Wrapper::DoStep(action, out);
  if (IsSuccess(out.info[success_index_])) *out.terminated = true;
}

}  // namespace manyworlds
