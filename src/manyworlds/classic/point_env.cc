#include "manyworlds/classic/point_env.h"

#include <cmath>
#include <limits>
#include <utility>

#include "manyworlds/classic/common.h"

namespace manyworlds::classic {

EnvSpec PointEnv::BaseSpec(const char* id, int64_t horizon) {
  CheckIntOption(id, "horizon", horizon, 1);
  const float inf = std::numeric_limits<float>::infinity();
  EnvSpec spec;
  spec.id = id;
  spec.action_space = Space::Box(-kMaxStep, kMaxStep, {2});
  spec.env_obs_space = Space::Box(-inf, inf, {2});
  spec.info_fields = {"success", "distance"};
  spec.max_episode_steps = horizon;
  spec.uses_env_seed = false;  // fixed start, deterministic moves
  return spec;
}

PointEnv::PointEnv(EnvSpec spec, bool hide_task) : Env(std::move(spec)), hide_task_(hide_task) {}

void PointEnv::SetGoal(double x, double y) {
  goal_ = {x, y};
  const float obs[2] = {hide_task_ ? 0.0f : static_cast<float>(goal_[0]),
                        hide_task_ ? 0.0f : static_cast<float>(goal_[1])};
  SetTaskObs(obs);
}

void PointEnv::DoReset(const ObsView& out) {
  position_ = {0.0, 0.0};
  out.env_obs[0] = 0.0f;
  out.env_obs[1] = 0.0f;
}

void PointEnv::DoStep(std::span<const float> action, const StepView& out) {
  position_[0] += action[0];
  position_[1] += action[1];
  const double distance = std::hypot(position_[0] - goal_[0], position_[1] - goal_[1]);
  out.env_obs[0] = static_cast<float>(position_[0]);
  out.env_obs[1] = static_cast<float>(position_[1]);
  *out.reward = Reward(distance);
  out.info[0] = Success(distance) ? 1.0f : 0.0f;
  out.info[1] = static_cast<float>(distance);
}

}  // namespace manyworlds::classic
