#include "manyworlds/manipulation/rotary/lever_pull.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kArm = 0.2;  // axis to grip (lever_pull.xml)
constexpr Vec3 kGoalOffset{0.12, 0.0, 0.25 + kArm};
constexpr double kUp = std::numbers::pi / 2;
constexpr double kSuccess = std::numbers::pi / 24;
// Hold the grip beside the arm, which meets it in the middle.
constexpr Vec3 kGraspBeside{0.035, 0.0, 0.0};

FixtureSpec Fixture() {
  FixtureSpec fixture{"lever_base", {}, "lever_hinge", 0.0, kGoalOffset};
  fixture.joint_qpos_sign = -1.0;  // v3's LeverAxis turns the other way
  return fixture;
}

Vec3 GraspPoint(const Vec3& grip) {
  return {grip[0] + kGraspBeside[0], grip[1] + kGraspBeside[1], grip[2] + kGraspBeside[2]};
}

}  // namespace

SawyerTaskConfig LeverPull::Config() {
  SawyerTaskConfig config = TaskConfig("lever-pull", "Sawyer arm: pull a lever up to vertical",
                                       "lever_pull.xml", {{-0.1, 0.7, 0.0}, {0.1, 0.8, 0.0}});
  config.hand_init = {0.0, 0.4, 0.2};
  UseGoalOffset(kGoalOffset, config);
  // v3's goal_space: its hand bounds, which reach z -0.15 (ours 0.05).
  config.goal_space = Range3{{-0.5, 0.4, -0.15}, {0.5, 1.0, 0.5}};
  return config;
}

LeverPull::LeverPull(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms LeverPull::ComputeReward(const SawyerState& s, std::span<const float>) const {
  // The hand's "shoulder" under the lever, compared with the grip, y
  // counting less.
  const ShoulderReach reach = ReachWithShoulder(s, s.handle_init, {4.0, 1.0, 4.0});
  const double shoulder_to_lever = reach.distance;
  const double ready = reach.ready;
  const double angle_error = std::abs(-s.joint_qpos - kUp);
  const double engagement = LongTailTolerance(angle_error, 0.0, std::numbers::pi / 48.0,
                                              kUp - std::numbers::pi / 12.0);
  const double in_place =
      LongTailTolerance(Distance(s.obj, s.goal), 0.0, 0.04, Distance(s.handle_init, s.goal));
  RewardTerms terms;
  terms.reward = 10.0 * HamacherProduct(ready, in_place);
  terms.success = angle_error <= kSuccess;
  terms.near_object = shoulder_to_lever < 0.03 ? 1.0 : 0.0;
  terms.grasp_success = ready > 0.9 ? 1.0 : 0.0;
  terms.grasp_reward = ready;
  terms.in_place_reward = engagement;
  terms.obj_to_target = shoulder_to_lever;
  return terms;
}

void LeverPull::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.v1_max_dist = Distance(s.goal, s.obj_init);  // v3's maxPullDist
}

RewardTerms LeverPull::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double pull_dist = Distance(s.obj, s.goal);
  RewardTerms terms;
  terms.reward = v1::ReachThenProgress(Distance(s.obj, s.tcp), s.v1_max_dist, pull_dist);
  // v3's evaluate_state on v1's (reward, 0, 0, pull_dist, 0): pull_dist is read as the
  // lever's angle error
  terms.success = pull_dist <= kSuccess;
  terms.near_object = 1.0;
  return terms;
}

void LeverPullScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 axis_point{o.goal[0], o.goal[1], o.goal[2] - kArm};
  const Vec3 grasp = GraspPoint(o.obj1);
  // About +x the lever's angle reads pi at rest and pi/2 when up.
  GraspAndMove(o, grasp, NextPointOnArc(grasp, axis_point, 0, kUp), -1.0, action);
}

}  // namespace manyworlds::manipulation
