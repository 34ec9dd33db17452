#include "manyworlds/core/wrappers/append_task_one_hot.h"

#include <algorithm>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

constexpr std::string_view kName = "task-one-hot";

std::unique_ptr<Env> CheckSpaces(std::unique_ptr<Env> inner) {
  if (!inner) return inner;  // Wrapper reports the null env
  const EnvSpec& spec = inner->spec();
  if (!spec.task_obs_space.is_discrete()) {
    throw ConfigError("wrapper " + std::string(kName) + " on env '" + spec.id +
                      "': needs a Discrete(n) task observation, got " +
                      spec.task_obs_space.ToString() +
                      " (wrap the env in NTasksId with TaskIdEncoding::kIndex, or use MultiEnv)");
  }
  if (!spec.env_obs_space.is_box()) {
    throw ConfigError("wrapper " + std::string(kName) + " on env '" + spec.id +
                      "': needs a Box env observation, got " + spec.env_obs_space.ToString());
  }
  return inner;
}

}  // namespace

AppendTaskOneHot::AppendTaskOneHot(std::unique_ptr<Env> inner)
    : Wrapper(CheckSpaces(std::move(inner)), kName) {
  const EnvSpec& inner_spec = this->inner().spec();
  inner_obs_size_ = inner_spec.env_obs_space.flat_size();
  num_tasks_ = inner_spec.task_obs_space.n();
  std::vector<float> low = inner_spec.env_obs_space.low();
  std::vector<float> high = inner_spec.env_obs_space.high();
  low.resize(inner_obs_size_ + num_tasks_, 0.0f);
  high.resize(inner_obs_size_ + num_tasks_, 1.0f);
  mutable_spec().env_obs_space =
      Space::Box(std::move(low), std::move(high), {inner_obs_size_ + num_tasks_});
}

void AppendTaskOneHot::WriteOneHot(std::span<float> env_obs) {
  // Read the id the inner env just reported: its task may have changed in
  // this Reset (SampleRandomTask below us).
  const int64_t id = static_cast<int64_t>(inner_task_obs()[0]);
  std::span<float> one_hot = env_obs.subspan(inner_obs_size_);
  std::fill(one_hot.begin(), one_hot.end(), 0.0f);
  one_hot[std::clamp<int64_t>(id, 0, num_tasks_ - 1)] = 1.0f;
}

void AppendTaskOneHot::DoReset(const ObsView& out) {
  Wrapper::DoReset(ObsView{out.env_obs.first(inner_obs_size_), out.task_obs, out.pixels});
  WriteOneHot(out.env_obs);
}

void AppendTaskOneHot::DoStep(std::span<const float> action, const StepView& out) {
  StepView inner_out = out;
  inner_out.env_obs = out.env_obs.first(inner_obs_size_);
  Wrapper::DoStep(action, inner_out);
  WriteOneHot(out.env_obs);
}

}  // namespace manyworlds
