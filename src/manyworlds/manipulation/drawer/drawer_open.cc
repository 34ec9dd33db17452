#include "manyworlds/manipulation/drawer/drawer_open.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{0.0, -0.36, 0.09};
constexpr double kSuccess = 0.03;
constexpr double kMaxDist = 0.2;  // v3's maxDist: the goal's pull, and a margin
// The bar's centre relative to the object point (drawer_fixture.xml).
constexpr Vec3 kBarFromPoint{0.0, 0.01, 0.0};
constexpr double kTravel = 0.2;  // the drawer's stop
// Pads at +-0.04 m while descending: the drawer face is 0.06 m behind the bar.
constexpr double kApproachGrip = -0.5;

FixtureSpec Fixture() { return {"drawer_case", {}, "drawer_slide", 0.0, kGoalOffset}; }

}  // namespace

SawyerTaskConfig DrawerOpen::Config() {
  SawyerTaskConfig config;
  config.id = "drawer-open";
  config.description = "Sawyer arm: pull a drawer open by its handle";
  config.xml_file = "drawer_open.xml";
  config.hand_init = {0.0, 0.6, 0.2};
  config.obj_low = {-0.1, 0.9, 0.0};
  config.obj_high = {0.1, 0.9, 0.0};
  config.obj_quat = QuatLayout::kWxyz;
  UseGoalOffset(kGoalOffset, config);
  return config;
}

DrawerOpen::DrawerOpen(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

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
  terms.success = handle_error <= kSuccess;
  terms.near_object = Distance(s.obj, s.hand) <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = s.gripper_opening > 0 ? 1.0 : 0.0;
  terms.grasp_reward = caging;
  terms.in_place_reward = opening;
  terms.obj_to_target = handle_error;
  return terms;
}

void DrawerOpen::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.v1_max_dist = kMaxDist;
}

RewardTerms DrawerOpen::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double pull_dist = std::abs(s.obj[1] - s.goal[1]);
  const double reach_dist = Distance(s.obj, s.tcp);
  RewardTerms terms;
  terms.reward = v1::ReachThenProgress(reach_dist, s.v1_max_dist, pull_dist);
  // v3's evaluate_state on v1's (reward, 0, 0, pull_dist, 0, 0)
  terms.success = pull_dist <= kSuccess;
  terms.near_object = 1.0;
  terms.grasp_success = 0.0;
  terms.obj_to_target = pull_dist;
  return terms;
}

void DrawerOpenScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 bar{o.obj1[0] + kBarFromPoint[0], o.obj1[1] + kBarFromPoint[1],
                 o.obj1[2] + kBarFromPoint[2]};
  // The shut bar is maxDist behind the goal (v3's handle_pos_init). Pull to
  // 1 cm past the stop, so the pull does not stall short of it.
  const double target_y = o.goal[1] + kMaxDist - kTravel - 0.01;
  GraspAndMove(o, bar, {bar[0], target_y, bar[2]}, kApproachGrip, action);
}

}  // namespace manyworlds::manipulation
