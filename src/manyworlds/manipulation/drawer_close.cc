#include "manyworlds/manipulation/drawer_close.h"

#include <cmath>

namespace manyworlds::manipulation {
namespace {

// The closed handle is at obj_pos + (0, -0.16, 0.09) (drawer_fixture.xml).
constexpr Vec3 kGoalOffset{0.0, -0.16, 0.09};
constexpr double kStartOpen = 0.2;
constexpr double kSuccess = 0.065;
// Closed pads reach 0.015 m past the tcp in y; the bar's radius is 0.008.
constexpr double kContactY = 0.023;
constexpr double kReadyY = 0.035;      // tcp in front of the bar before pushing
constexpr double kHoverHeight = 0.08;  // above the bar while getting in front

FixtureSpec Fixture() { return {"drawer_case", {}, "drawer_slide", kStartOpen, kGoalOffset}; }

}  // namespace

SawyerTaskConfig DrawerClose::Config() {
  SawyerTaskConfig config;
  config.id = "drawer-close";
  config.description = "Sawyer arm: push an open drawer shut";
  config.xml_file = "drawer_close.xml";
  config.hand_init = {0.0, 0.6, 0.2};
  config.obj_low = {-0.1, 0.9, 0.0};
  config.obj_high = {0.1, 0.9, 0.0};
  UseGoalOffset(kGoalOffset, config);
  return config;
}

DrawerClose::DrawerClose(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms DrawerClose::ComputeReward(const SawyerState& s, std::span<const float>) const {
  return MoveHandleReward(s, handle_init(), kSuccess);
}

void DrawerCloseScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                    std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3& bar = o.obj1;
  const auto hand_for_tcp = [](double x, double y, double z) {
    return Vec3{x, y, z + kTcpBelowHand};
  };
  const bool in_front = o.tcp[1] < bar[1] - 0.015;
  const bool centred = std::abs(o.tcp[0] - bar[0]) < 0.01;
  if (in_front && centred && std::abs(o.tcp[2] - bar[2]) < 0.01) {
    // Push until the bar is 1 cm past shut; the slide's limit stops it.
    MoveTo(o.hand, hand_for_tcp(bar[0], o.goal[1] + 0.01 - kContactY, bar[2]), 1.0, action);
  } else if (in_front && centred) {
    MoveTo(o.hand, hand_for_tcp(bar[0], bar[1] - kReadyY, bar[2]), 1.0, action);
  } else {
    MoveTo(o.hand, hand_for_tcp(bar[0], bar[1] - kReadyY, bar[2] + kHoverHeight), 1.0, action);
  }
}

}  // namespace manyworlds::manipulation
