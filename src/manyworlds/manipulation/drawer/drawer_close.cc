#include "manyworlds/manipulation/drawer/drawer_close.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

// The shut bar is at obj_pos + (0, -0.16, 0.09) (drawer_fixture.xml).
constexpr Vec3 kGoalOffset{0.0, -0.16, 0.09};
constexpr double kStartOpen = 0.15;
constexpr double kTargetRadius = 0.05;  // v3's TARGET_RADIUS
constexpr double kSuccess = kTargetRadius + 0.015;
// v3's object point: 1 cm in front of the bar (as drawer-open's) and 5 cm
// above it.
constexpr Vec3 kPointAbove{0.0, 0.0, 0.05};
constexpr Vec3 kBarFromPoint{0.0, 0.01, -0.05};
// Closed pads reach 0.015 m past the tcp in y; the bar's radius is 0.008.
constexpr double kContactY = 0.023;
constexpr double kReadyY = 0.035;      // tcp in front of the bar before pushing
constexpr double kHoverHeight = 0.08;  // above the bar while getting in front

FixtureSpec Fixture() {
  FixtureSpec fixture{"drawer_case", {}, "drawer_slide", kStartOpen, kGoalOffset};
  fixture.obj_origin_shift = kPointAbove;
  fixture.obj_init_is_object_point = true;
  return fixture;
}

}  // namespace

SawyerTaskConfig DrawerClose::Config() {
  SawyerTaskConfig config;
  config.id = "drawer-close";
  config.description = "Sawyer arm: push an open drawer shut";
  config.xml_file = "drawer_close.xml";
  config.hand_init = {0.0, 0.6, 0.2};
  config.obj_low = {-0.1, 0.9, 0.0};
  config.obj_high = {0.1, 0.9, 0.0};
  config.obj_quat = QuatLayout::kZeros;
  UseGoalOffset(kGoalOffset, config);
  return config;
}

DrawerClose::DrawerClose(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms DrawerClose::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  constexpr double kReachRadius = 0.005;
  const double target_to_obj = Distance(s.obj, s.goal);
  const double in_place =
      LongTailTolerance(target_to_obj, 0.0, kTargetRadius,
                        std::abs(Distance(s.obj_init, s.goal) - kTargetRadius));
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  const double near = GaussianTolerance(tcp_to_obj, 0.0, kReachRadius,
                                        std::abs(Distance(s.obj_init, s.tcp_init) - kReachRadius));
  const double closed = std::clamp(static_cast<double>(action[3]), 0.0, 1.0);
  const double reach = HamacherProduct(near, closed);
  const bool success = target_to_obj <= kSuccess;
  RewardTerms terms;
  terms.reward = 10.0 * (success ? 1.0 : HamacherProduct(reach, in_place));
  terms.success = success;
  terms.near_object = tcp_to_obj <= 0.01 ? 1.0 : 0.0;
  terms.grasp_success = 1.0;
  terms.grasp_reward = reach;
  terms.in_place_reward = in_place;
  terms.obj_to_target = target_to_obj;
  return terms;
}

void DrawerClose::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.v1_max_dist = kStartOpen;
}

RewardTerms DrawerClose::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double pull_dist = std::abs(s.obj[1] - s.goal[1]);
  const double reach_dist = Distance(s.obj, s.tcp);
  RewardTerms terms;
  terms.reward = v1::ReachThenProgress(reach_dist, s.v1_max_dist, pull_dist);
  // v3's evaluate_state on v1's (reward, 0, 0, pull_dist, 0, 0)
  terms.success = pull_dist <= kSuccess;
  terms.near_object = 1.0;
  terms.grasp_success = 1.0;
  terms.obj_to_target = pull_dist;
  return terms;
}

void DrawerCloseScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                    std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 bar{o.obj1[0] + kBarFromPoint[0], o.obj1[1] + kBarFromPoint[1],
                 o.obj1[2] + kBarFromPoint[2]};
  const auto hand_for_tcp = [](double x, double y, double z) {
    return Vec3{x, y, z + kTcpBelowHand};
  };
  const bool in_front = o.tcp[1] < bar[1] - 0.015;
  const bool centred = std::abs(o.tcp[0] - bar[0]) < 0.01;
  if (in_front && centred && std::abs(o.tcp[2] - bar[2]) < 0.01) {
    // Push until the bar is 1 cm past shut (the goal); the slide's limit
    // stops it.
    MoveTo(o.hand, hand_for_tcp(bar[0], o.goal[1] + 0.01 - kContactY, bar[2]), 1.0, action);
  } else if (in_front && centred) {
    MoveTo(o.hand, hand_for_tcp(bar[0], bar[1] - kReadyY, bar[2]), 1.0, action);
  } else {
    MoveTo(o.hand, hand_for_tcp(bar[0], bar[1] - kReadyY, bar[2] + kHoverHeight), 1.0, action);
  }
}

}  // namespace manyworlds::manipulation
