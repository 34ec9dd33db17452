#include "manyworlds/core/wrappers/action_repeat.h"

#include <algorithm>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

std::unique_ptr<Env> CheckRepeat(std::unique_ptr<Env> inner, int64_t repeat) {
  if (repeat < 1 || repeat > ActionRepeat::kMaxRepeat) {
    throw ConfigError("wrapper action-repeat: repeat must be in [1, " +
                      std::to_string(ActionRepeat::kMaxRepeat) + "], got " +
                      std::to_string(repeat));
  }
  return inner;
}

}  // namespace

ActionRepeat::ActionRepeat(std::unique_ptr<Env> inner, int64_t repeat)
    : Wrapper(CheckRepeat(std::move(inner), repeat), "action-repeat"), repeat_(repeat) {
  const EnvSpec& s = this->inner().spec();
  success_index_ = s.InfoIndex("success");
  info_.assign(s.info_fields.size(), 0.0f);
  if (s.max_episode_steps > 0) {
    Env::SetMaxEpisodeSteps((s.max_episode_steps + repeat_ - 1) / repeat_);
  }
}

void ActionRepeat::SetMaxEpisodeSteps(int64_t max_episode_steps) {
  inner().SetMaxEpisodeSteps(max_episode_steps * repeat_);
  Env::SetMaxEpisodeSteps(max_episode_steps);
}

void ActionRepeat::DoStep(std::span<const float> action, const StepView& out) {
  float total = 0.0f;
  float success = 0.0f;
  for (int64_t k = 0; k < repeat_; ++k) {
    StepView step = out;
    step.info = info_;
    Wrapper::DoStep(action, step);
    total += *out.reward;
    if (success_index_ >= 0) success = std::max(success, info_[success_index_]);
    if (*out.terminated || *out.truncated) break;
  }
  std::copy(info_.begin(), info_.end(), out.info.begin());
  if (success_index_ >= 0) out.info[success_index_] = success;
  *out.reward = total;
}

}  // namespace manyworlds
