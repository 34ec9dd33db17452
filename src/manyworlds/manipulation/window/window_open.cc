#include "manyworlds/manipulation/window/window_open.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{0.2, 0.0, 0.0};
// The frame (root body) stands on the table with the shut handle bar at
// obj_pos + (-0.014, -0.095, 0), 0.16 m up.
constexpr Vec3 kFrameOffset{-0.014, -0.095, -0.16};
// The handle bar's x relative to the object point (the obj body).
constexpr double kBarFromPoint = 0.026;
// The shut bar's x relative to the goal.
constexpr double kBarX = 0.014;
constexpr double kTargetRadius = 0.05;  // v3's TARGET_RADIUS

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
  config.obj_quat = QuatLayout::kZeros;
  UseGoalOffset(kGoalOffset, config);
  return config;
}

WindowOpen::WindowOpen(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms WindowOpen::ComputeReward(const SawyerState& s, std::span<const float>) const {
  constexpr double kHandleRadius = 0.02;
  const double target_to_obj = std::abs(s.obj[0] - s.goal[0]);
  const double in_place = LongTailTolerance(target_to_obj, 0.0, kTargetRadius,
                                            std::abs(std::abs(s.obj_init[0] - s.goal[0]) - kTargetRadius));
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  const double reach = LongTailTolerance(tcp_to_obj, 0.0, kHandleRadius,
                                          std::abs(Distance(s.handle_init, s.tcp_init) - kHandleRadius));
  RewardTerms terms;
  terms.reward = 10.0 * HamacherProduct(reach, in_place);
  terms.success = target_to_obj <= kTargetRadius;
  terms.near_object = tcp_to_obj <= 0.05 ? 1.0 : 0.0;
  terms.grasp_success = 1.0;
  terms.grasp_reward = reach;
  terms.in_place_reward = in_place;
  terms.obj_to_target = target_to_obj;
  return terms;
}

void WindowOpen::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.v1_max_dist = 0.2;  // v3's maxPullDist, a constant
}

RewardTerms WindowOpen::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double pull_dist = std::abs(s.obj[0] - s.goal[0]);
  const double reach_dist = Distance(s.obj, s.tcp);
  RewardTerms terms;
  // v3 does not clamp this bonus at 0
  terms.reward = v1::ReachThenProgress(reach_dist, s.v1_max_dist, pull_dist, /*clamp=*/false);
  // v3's evaluate_state on v1's (reward, 0, 0, pull_dist, 0, 0)
  terms.success = pull_dist <= kTargetRadius;
  terms.near_object = 1.0;
  terms.grasp_success = 1.0;
  terms.obj_to_target = pull_dist;
  return terms;
}

void WindowOpenScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 bar{o.obj1[0] + kBarFromPoint, o.obj1[1], o.obj1[2]};
  // To the stop, fully open: the bar 0.014 m short of the goal in x.
  PushBarAlongX(o, bar, o.goal[0] - kBarX, action);
}

}  // namespace manyworlds::manipulation
