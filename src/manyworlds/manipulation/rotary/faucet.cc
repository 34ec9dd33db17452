#include "manyworlds/manipulation/rotary/faucet.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/manipulation/bar_push.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kArm = 0.175;        // axis to the arm's end
constexpr double kAxisHeight = 0.124; // above obj_pos
constexpr double kGoalHeight = 0.125;
constexpr double kTargetRadius = 0.07;
constexpr double kReachRadius = 0.01;
// v3's object sites sit 1.5 cm beside the arm's end.
constexpr double kSiteSide = 0.015;

FixtureSpec Fixture(double side) {
  FixtureSpec fixture{"faucet_base", {}, "faucet_hinge", 0.0, {side * kArm, 0.0, kGoalHeight}};
  fixture.obj_origin_shift = {-side * kSiteSide, 0.0, 0.0};
  return fixture;
}

// side: +1 faucet-open (the goal to the right), -1 faucet-close.
SawyerTaskConfig FaucetConfig(double side, const char* id, const char* description,
                              const Range3& obj) {
  SawyerTaskConfig config =
      TaskConfig(id, description, side > 0 ? "faucet_open.xml" : "faucet_close.xml", obj);
  config.hand_init = {0.0, 0.4, 0.2};
  config.hand_low = {-0.5, 0.4, -0.15};
  config.hand_high = {0.5, 1.0, 0.5};
  config.obj_quat = QuatLayout::kWxyz;
  config.obj_quat_body = "faucet_base";
  UseGoalOffset({side * kArm, 0.0, kGoalHeight}, config);
  config.goal_space = Range3{config.hand_low, config.hand_high};  // v3's: the hand's range
  return config;
}

RewardTerms FaucetReward(const SawyerState& s, const Vec3& p) {
  const double target_to_obj = Distance(p, s.goal);
  const double in_place = LongTailTolerance(target_to_obj, 0.0, kTargetRadius,
                                            std::abs(Distance(s.obj_init, s.goal) - kTargetRadius));
  const double tcp_to_obj = Distance(p, s.tcp);
  const double reach = GaussianTolerance(
      tcp_to_obj, 0.0, kReachRadius, std::abs(Distance(s.obj_init, s.tcp_init) - kReachRadius));
  RewardTerms terms;
  terms.success = target_to_obj <= kTargetRadius;
  terms.reward = terms.success ? 10.0 : 2.0 * (2.0 * reach + 3.0 * in_place);
  terms.near_object = tcp_to_obj <= kReachRadius ? 1.0 : 0.0;
  terms.grasp_success = 1.0;
  terms.grasp_reward = reach;
  terms.in_place_reward = in_place;
  terms.obj_to_target = target_to_obj;
  return terms;
}

void FaucetInitV1(SawyerState& s) { s.v1_max_dist = Distance(s.goal, s.obj_init); }

RewardTerms FaucetRewardV1(const SawyerState& s) {
  return v1::ReachThenProgressStep(s, Distance(s.obj, s.tcp), Distance(s.obj, s.goal),
                                   kTargetRadius, /*grasp_success=*/1.0);
}

}  // namespace

template <int kSide>
SawyerTaskConfig Faucet<kSide>::Config() {
  if (kSide > 0) {
    return FaucetConfig(1.0, "faucet-open", "Sawyer arm: turn a faucet's handle to the right",
                        {{-0.05, 0.8, 0.0}, {0.05, 0.85, 0.0}});
  }
  return FaucetConfig(-1.0, "faucet-close", "Sawyer arm: turn a faucet's handle to the left",
                      {{-0.1, 0.8, 0.0}, {0.1, 0.85, 0.0}});
}

template <int kSide>
Faucet<kSide>::Faucet(SawyerOptions options)
    : ArticulatedTask(Config(), Fixture(kSide), options) {}

template <int kSide>
RewardTerms Faucet<kSide>::ComputeReward(const SawyerState& s, std::span<const float>) const {
  // opening, v3 moves the object point 4 cm left and 3 cm up before it compares it
  if (kSide > 0) return FaucetReward(s, {s.obj[0] - 0.04, s.obj[1], s.obj[2] + 0.03});
  return FaucetReward(s, s.obj);
}

template <int kSide>
void Faucet<kSide>::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  FaucetInitV1(s);
}

template <int kSide>
RewardTerms Faucet<kSide>::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return FaucetRewardV1(s);
}

template class Faucet<1>;
template class Faucet<-1>;

void FaucetScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                               std::span<float> action) {
  const SawyerObs o(env_obs);
  // The axis is the goal less the arm toward the goal's side (open: +x); of
  // the two candidates, the object point lies at the arm's length from the
  // right one (both only at the goal itself).
  rotary::BarPush push;
  const double reach = std::hypot(kArm, kSiteSide);
  const auto off_arm = [&](double side) {
    return std::abs(std::hypot(o.obj1[0] - (o.goal[0] - side * kArm), o.obj1[1] - o.goal[1]) -
                    reach);
  };
  const double side = off_arm(1.0) < off_arm(-1.0) ? 1.0 : -1.0;
  push.center = {o.goal[0] - side * kArm, o.goal[1], o.goal[2] - kGoalHeight + kAxisHeight};
  // The arm's direction: from the axis to the object point, less the site's
  // sideways offset (small; it only sets where along the grip to push).
  push.bar_angle = std::atan2(o.obj1[1] - push.center[1], o.obj1[0] - push.center[0]) +
                   side * std::atan2(kSiteSide, kArm);
  push.direction = side > 0 ? 1 : -1;
  push.push_at = 0.14;
  push.height = push.center[2];
  push.standoff = 0.035;
  rotary::PushBarAround(o, push, action);
}

}  // namespace manyworlds::manipulation
