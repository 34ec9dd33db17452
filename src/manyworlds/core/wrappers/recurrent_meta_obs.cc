#include "manyworlds/core/wrappers/recurrent_meta_obs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

std::unique_ptr<Env> CheckObs(std::unique_ptr<Env> inner, double reward_scale) {
  if (!inner) return inner;  // Wrapper reports the null env
  if (!inner->spec().env_obs_space.is_box()) {
    throw ConfigError("wrapper recurrent-meta-obs on env '" + inner->spec().id +
                      "': needs a Box env observation, got " +
                      inner->spec().env_obs_space.ToString());
  }
  if (!std::isfinite(reward_scale)) {
    throw ConfigError("wrapper recurrent-meta-obs: reward_scale must be finite");
  }
  return inner;
}

}  // namespace

RecurrentMetaObservation::RecurrentMetaObservation(std::unique_ptr<Env> inner,
                                                   double reward_scale)
    : Wrapper(CheckObs(std::move(inner), reward_scale), "recurrent-meta-obs"),
      reward_scale_(static_cast<float>(reward_scale)) {
  const EnvSpec& s = this->inner().spec();
  inner_obs_size_ = s.env_obs_space.flat_size();
  std::vector<float> low = s.env_obs_space.low();
  std::vector<float> high = s.env_obs_space.high();
  if (s.action_space.is_discrete()) {
    num_actions_ = s.action_space.n();
    action_size_ = num_actions_;
    low.insert(low.end(), action_size_, 0.0f);
    high.insert(high.end(), action_size_, 1.0f);
  } else {
    action_size_ = s.action_space.flat_size();
    low.insert(low.end(), s.action_space.low().begin(), s.action_space.low().end());
    high.insert(high.end(), s.action_space.high().begin(), s.action_space.high().end());
  }
  constexpr float kInf = std::numeric_limits<float>::infinity();
  low.push_back(-kInf);
  high.push_back(kInf);
  low.push_back(0.0f);
  high.push_back(1.0f);
  const int64_t size = inner_obs_size_ + action_size_ + 2;
  mutable_spec().env_obs_space = Space::Box(std::move(low), std::move(high), {size});
}

void RecurrentMetaObservation::DoReset(const ObsView& out) {
  Wrapper::DoReset(ObsView{out.env_obs.first(inner_obs_size_), out.task_obs, out.pixels});
  std::span<float> extra = out.env_obs.subspan(inner_obs_size_);
  std::fill(extra.begin(), extra.end(), 0.0f);
}

void RecurrentMetaObservation::DoStep(std::span<const float> action, const StepView& out) {
  StepView inner_out = out;
  inner_out.env_obs = out.env_obs.first(inner_obs_size_);
  Wrapper::DoStep(action, inner_out);
  std::span<float> extra = out.env_obs.subspan(inner_obs_size_);
  if (num_actions_ > 0) {
    std::fill(extra.begin(), extra.begin() + action_size_, 0.0f);
    const auto index = static_cast<int64_t>(action[0]);
    extra[std::clamp<int64_t>(index, 0, num_actions_ - 1)] = 1.0f;
  } else {
    std::copy(action.begin(), action.begin() + action_size_, extra.begin());
  }
  extra[action_size_] = *out.reward * reward_scale_;
  extra[action_size_ + 1] = *out.terminated || *out.truncated ? 1.0f : 0.0f;
}

}  // namespace manyworlds
