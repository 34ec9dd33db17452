#include "manyworlds/manipulation/drawer/drawer.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

// drawer-open
constexpr Vec3 kOpenGoalOffset{0.0, -0.36, 0.09};
constexpr double kOpenSuccess = 0.03;
constexpr double kMaxDist = 0.2;  // v3's maxDist: the goal's pull, and a margin
// The bar's centre relative to the object point (drawer_fixture.xml).
constexpr Vec3 kOpenBarFromPoint{0.0, 0.01, 0.0};
constexpr double kTravel = 0.2;  // the drawer's stop
// Pads at +-0.04 m while descending: the drawer face is 0.06 m behind the bar.
constexpr double kApproachGrip = -0.5;

// drawer-close. The shut bar is at obj_pos + (0, -0.16, 0.09)
// (drawer_fixture.xml).
constexpr Vec3 kCloseGoalOffset{0.0, -0.16, 0.09};
constexpr double kStartOpen = 0.15;
constexpr double kTargetRadius = 0.05;  // v3's TARGET_RADIUS
constexpr double kCloseSuccess = kTargetRadius + 0.015;
// v3's object point: 1 cm in front of the bar (as drawer-open's) and 5 cm
// above it.
constexpr Vec3 kPointAbove{0.0, 0.0, 0.05};
constexpr Vec3 kCloseBarFromPoint{0.0, 0.01, -0.05};
// Closed pads reach 0.015 m past the tcp in y; the bar's radius is 0.008.
constexpr double kContactY = 0.023;
constexpr double kReadyY = 0.035;      // tcp in front of the bar before pushing
constexpr double kHoverHeight = 0.08;  // above the bar while getting in front

FixtureSpec OpenFixture() { return {"drawer_case", {}, "drawer_slide", 0.0, kOpenGoalOffset}; }

FixtureSpec CloseFixture() {
  FixtureSpec fixture{"drawer_case", {}, "drawer_slide", kStartOpen, kCloseGoalOffset};
  fixture.obj_origin_shift = kPointAbove;
  fixture.obj_init_is_object_point = true;
  return fixture;
}

Vec3 Bar(const SawyerObs& o, const Vec3& bar_from_point) {
  return {o.obj1[0] + bar_from_point[0], o.obj1[1] + bar_from_point[1],
          o.obj1[2] + bar_from_point[2]};
}

}  // namespace

DrawerTask::DrawerTask(SawyerTaskConfig config, FixtureSpec fixture, DrawerV1 v1,
                       SawyerOptions options)
    : ArticulatedTask(std::move(config), std::move(fixture), options), v1_(v1) {}

SawyerTaskConfig DrawerTask::DrawerConfig(const char* id, const char* description,
                                          const char* xml_file, QuatLayout obj_quat,
                                          const Vec3& goal_offset) {
  SawyerTaskConfig config;
  config.id = id;
  config.description = description;
  config.xml_file = xml_file;
  config.hand_init = {0.0, 0.6, 0.2};
  config.obj_low = {-0.1, 0.9, 0.0};
  config.obj_high = {0.1, 0.9, 0.0};
  config.obj_quat = obj_quat;
  UseGoalOffset(goal_offset, config);
  config.goal_space = Range3{config.hand_low, config.hand_high};  // v3's: the hand's range
  return config;
}

void DrawerTask::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.v1_max_dist = v1_.max_dist;
}

RewardTerms DrawerTask::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return v1::ReachThenProgressStep(s, Distance(s.obj, s.tcp), std::abs(s.obj[1] - s.goal[1]),
                                   v1_.success, v1_.grasp_success);
}

SawyerTaskConfig DrawerOpen::Config() {
  return DrawerConfig("drawer-open", "Sawyer arm: pull a drawer open by its handle",
                      "drawer_open.xml", QuatLayout::kWxyz, kOpenGoalOffset);
}

DrawerOpen::DrawerOpen(SawyerOptions options)
    : DrawerTask(Config(), OpenFixture(), {kOpenSuccess, kMaxDist, 0.0}, options) {}

RewardTerms DrawerOpen::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double handle_error = Distance(s.obj, s.goal);
  const double opening = LongTailTolerance(handle_error, 0.0, 0.02, kMaxDist);
  // Where v3 takes the shut handle to be: the goal pushed back maxDist.
  const Vec3 handle_init{s.goal[0], s.goal[1] + kMaxDist, s.goal[2]};
  // x and y weigh more, so the gripper may rise over the handle and drop
  // down behind it without losing much.
  constexpr Vec3 kScale{3.0, 3.0, 1.0};
  const double caging = LongTailTolerance(WeightedDistance(s.obj, s.hand, kScale), 0.0, 0.01,
                                          WeightedDistance(handle_init, s.tcp_init, kScale));
  RewardTerms terms;
  terms.reward = 5.0 * (caging + opening);
  terms.success = handle_error <= kOpenSuccess;
  terms.near_object = Distance(s.obj, s.hand) <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = s.gripper_opening > 0 ? 1.0 : 0.0;
  terms.grasp_reward = caging;
  terms.in_place_reward = opening;
  terms.obj_to_target = handle_error;
  return terms;
}

SawyerTaskConfig DrawerClose::Config() {
  return DrawerConfig("drawer-close", "Sawyer arm: push an open drawer shut", "drawer_close.xml",
                      QuatLayout::kZeros, kCloseGoalOffset);
}

DrawerClose::DrawerClose(SawyerOptions options)
    : DrawerTask(Config(), CloseFixture(), {kCloseSuccess, kStartOpen, 1.0}, options) {}

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
  return ReachAndMoveTerms({.reach = reach, .in_place = in_place, .obj_to_target = target_to_obj,
                            .success = target_to_obj <= kCloseSuccess,
                            .near = tcp_to_obj <= 0.01, .ten_at_success = true});
}

void DrawerOpenScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 bar = Bar(o, kOpenBarFromPoint);
  // The shut bar is maxDist behind the goal (v3's handle_pos_init). Pull to
  // 1 cm past the stop, so the pull does not stall short of it.
  const double target_y = o.goal[1] + kMaxDist - kTravel - 0.01;
  GraspAndMove(o, bar, {bar[0], target_y, bar[2]}, kApproachGrip, action);
}

void DrawerCloseScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                    std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 bar = Bar(o, kCloseBarFromPoint);
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
