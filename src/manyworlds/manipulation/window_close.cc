#include "manyworlds/manipulation/window_close.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{0.0, 0.0, 0.0};  // the goal is the shut handle
constexpr double kStartOpen = 0.2;
// The frame (root body) stands on the table, 0.2 m under the handle.
constexpr Vec3 kFrameOffset{0.0, 0.0, -0.2};
constexpr double kSuccess = 0.05;

FixtureSpec Fixture() {
  return {"window_frame", kFrameOffset, "window_slide", kStartOpen, kGoalOffset};
}

}  // namespace

SawyerTaskConfig WindowClose::Config() {
  SawyerTaskConfig config;
  config.id = "window-close";
  config.description = "Sawyer arm: slide an open window shut by its handle";
  config.xml_file = "window_close.xml";
  config.hand_init = {0.0, 0.4, 0.2};
  config.obj_low = {0.0, 0.75, 0.2};
  config.obj_high = {0.0, 0.9, 0.2};
  UseGoalOffset(kGoalOffset, config);
  return config;
}

WindowClose::WindowClose(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms WindowClose::ComputeReward(const SawyerState& s, std::span<const float>) const {
  return MoveHandleReward(s, handle_init(), kSuccess);
}

void WindowCloseScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                    std::span<float> action) {
  const SawyerObs o(env_obs);
  PushBarAlongX(o, o.obj1, o.goal[0], action);
}

}  // namespace manyworlds::manipulation
