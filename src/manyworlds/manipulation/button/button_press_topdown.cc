#include "manyworlds/manipulation/button/button_press_topdown.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kCapTop = 0.1935;  // the cap's top at rest, above obj_pos
constexpr double kTravel = 0.0935;  // rest to fully pressed (the goal)
constexpr Vec3 kGoalOffset{0.0, 0.0, kCapTop - kTravel};
// The box (root body) stands on the table, 0.115 m under obj_pos.
constexpr Vec3 kBoxOffset{0.0, 0.0, -0.115};
constexpr double kSuccess = 0.024;
// Closed pads reach 0.012 m below the tcp.
constexpr double kPadsBelowTcp = 0.012;
constexpr double kHoverHeight = 0.05;  // tcp above the cap top while aligning

FixtureSpec Fixture() { return {"button_box", kBoxOffset, "button_slide", 0.0, kGoalOffset}; }

}  // namespace

SawyerTaskConfig ButtonPressTopdown::Config() {
  SawyerTaskConfig config =
      TaskConfig("button-press-topdown", "Sawyer arm: press a button on top of a box",
                 "button_press_topdown.xml", {{-0.1, 0.8, 0.115}, {0.1, 0.9, 0.115}});
  config.hand_init = {0.0, 0.4, 0.2};
  config.obj_quat = QuatLayout::kWxyz;
  UseGoalOffset(kGoalOffset, config);
  config.goal_space = Range3{config.hand_low, config.hand_high};  // v3's: the hand's range
  return config;
}

ButtonPressTopdown::ButtonPressTopdown(SawyerOptions options)
    : ArticulatedTask(Config(), Fixture(), options) {}

ButtonPressTopdown::ButtonPressTopdown(SawyerTaskConfig config, SawyerOptions options)
    : ArticulatedTask(std::move(config), Fixture(), options) {}

void ButtonPressTopdown::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.obj_to_target_init = std::abs(s.obj[2] - s.goal[2]);
  s.v1_max_dist = s.obj_to_target_init;  // v3's maxDist: the same |buttonStart.z - goal.z|
}

RewardTerms ButtonPressTopdown::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  const double obj_to_target = std::abs(s.goal[2] - s.obj[2]);
  const double near_button = LongTailTolerance(tcp_to_obj, 0.0, 0.01, Distance(s.obj, s.tcp_init));
  const double pressed = LongTailTolerance(obj_to_target, 0.0, 0.005, s.obj_to_target_init);
  double reward = 5.0 * HamacherProduct(1.0 - s.gripper_opening, near_button);
  if (tcp_to_obj <= 0.03) reward += 5.0 * pressed;
  return PressRewardTerms(s, {.reward = reward, .obj_to_target = obj_to_target,
                              .success_radius = kSuccess, .tcp_to_obj = tcp_to_obj,
                              .near = near_button, .pressed = pressed});
}

RewardTerms ButtonPressTopdown::ComputeRewardV1(const SawyerState& s,
                                                 std::span<const float>) const {
  return v1::ReachThenProgressStep(s, Distance(s.obj, s.tcp), std::abs(s.obj[2] - s.goal[2]),
                                   kSuccess);
}

void ButtonPressTopdownScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                           std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3& top = o.obj1;
  const double xy_error = std::hypot(o.tcp[0] - top[0], o.tcp[1] - top[1]);
  const bool low = o.tcp[2] < top[2] + 0.6 * kHoverHeight;
  double tcp_z;
  if (xy_error > 0.015 || (xy_error > 0.008 && !low)) {
    tcp_z = std::max(o.tcp[2], top[2] + kHoverHeight);  // align first, never lower
  } else {
    // Pads at the goal: the button pressed fully (its stop).
    tcp_z = o.goal[2] + kPadsBelowTcp;
  }
  MoveTo(o.hand, {top[0], top[1], tcp_z + kTcpBelowHand}, 1.0, action);
}

}  // namespace manyworlds::manipulation
