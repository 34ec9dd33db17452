#include "manyworlds/manipulation/rotary/dial_turn.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/manipulation/bar_push.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{0.0, 0.03, 0.03};
constexpr Vec3 kPushOffset{0.05, 0.02, 0.09};
constexpr double kTargetRadius = 0.07;
constexpr double kReachRadius = 0.005;

Vec3 PushPoint(const Vec3& obj) {
  return {obj[0] + kPushOffset[0], obj[1] + kPushOffset[1], obj[2] + kPushOffset[2]};
}

}  // namespace

SawyerTaskConfig DialTurn::Config() {
  SawyerTaskConfig config = TaskConfig("dial-turn", "Sawyer arm: turn a dial", "dial_turn.xml",
                                       {{-0.1, 0.7, 0.0}, {0.1, 0.8, 0.0}});
  config.hand_init = {0.0, 0.6, 0.2};
  config.obj_quat = QuatLayout::kWxyz;
  config.obj_quat_body = "dial_base";
  UseGoalOffset(kGoalOffset, config);
  // v3's goal_space: the goals' box with z widened 0.1 mm either way.
  config.goal_space = Range3{{-0.1, 0.73, 0.0299}, {0.1, 0.83, 0.0301}};
  return config;
}

DialTurn::DialTurn(SawyerOptions options)
    : ArticulatedTask(Config(), FixtureSpec{"dial_base", {}, "dial_hinge", 0.0, kGoalOffset},
                      options) {}

void DialTurn::InitTaskState(SawyerState& state) const {
  ArticulatedTask::InitTaskState(state);
  state.handle_init = PushPoint(state.obj);
  state.v1_max_dist = std::abs(state.goal[1] - state.obj_init[1]);  // v3's maxPullDist
}

RewardTerms DialTurn::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return v1::ReachThenProgressStep(s, Distance(s.obj, s.tcp), std::abs(s.obj[1] - s.goal[1]),
                                   kTargetRadius, /*grasp_success=*/1.0);
}

RewardTerms DialTurn::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const Vec3 push = PushPoint(s.obj);
  const double target_to_obj = Distance(s.obj, s.goal);
  const double in_place =
      LongTailTolerance(target_to_obj, 0.0, kTargetRadius,
                        std::abs(Distance(s.handle_init, s.goal) - kTargetRadius));
  const double tcp_to_push = Distance(push, s.tcp);
  const double gripper_closed = std::clamp(static_cast<double>(action[3]), 0.0, 1.0);
  const double reach = HamacherProduct(
      GaussianTolerance(tcp_to_push, 0.0, kReachRadius,
                        std::abs(Distance(s.handle_init, s.tcp_init) - kReachRadius)),
      gripper_closed);
  return ReachAndMoveTerms({.reach = reach, .in_place = in_place, .obj_to_target = target_to_obj,
                            .success = target_to_obj <= kTargetRadius,
                            .near = tcp_to_push <= 0.01});
}

void DialTurnScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                 std::span<float> action) {
  const SawyerObs o(env_obs);
  rotary::BarPush push;
  push.center = {o.goal[0] - kGoalOffset[0], o.goal[1] - kGoalOffset[1], 0.0};
  // The ridge's half toward the object point (at -y at rest).
  push.bar_angle = std::atan2(o.obj1[1] - push.center[1], o.obj1[0] - push.center[0]);
  push.direction = -1;
  push.push_at = 0.032;
  push.height = o.goal[2] - kGoalOffset[2] + 0.052;
  push.standoff = 0.032;
  rotary::PushBarAround(o, push, action);
}

}  // namespace manyworlds::manipulation
