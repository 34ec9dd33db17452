#include "manyworlds/manipulation/window_open.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{0.2, 0.0, 0.0};
// The frame (root body) stands on the table, 0.16 m under the handle.
constexpr Vec3 kFrameOffset{0.0, 0.0, -0.16};
constexpr double kSuccess = 0.05;

FixtureSpec Fixture() { return {"window_frame", kFrameOffset, "window_slide", 0.0, kGoalOffset}; }

}  // namespace

SawyerTaskConfig WindowOpen::Config() {
  SawyerTaskConfig config;
  config.id = "window-open";
  config.description = "Sawyer arm: slide a window open by its handle";
  config.xml_file = "window_open.xml";
  config.hand_init = {0.0, 0.4, 0.2};
  config.obj_low = {-0.1, 0.7, 0.16};
  config.obj_high = {0.1, 0.9, 0.16};
  UseGoalOffset(kGoalOffset, config);
  return config;
}

WindowOpen::WindowOpen(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms WindowOpen::ComputeReward(const SawyerState& s, std::span<const float>) const {
  return MoveHandleReward(s, handle_init(), kSuccess);
}

void WindowOpenScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  PushBarAlongX(o, o.obj1, o.goal[0], action);
}

}  // namespace manyworlds::manipulation
