#include "manyworlds/manipulation/door/door_close.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/door/door_fixture.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{0.2, -0.2, 0.0};
constexpr double kSuccess = 0.08;
constexpr double kStartAngle = -1.5708;  // hinge position at reset (open), as v3
// Push to shut (the hinge's limit); success comes within about 9 degrees of
// it.
constexpr double kShut = 0.0;

}  // namespace

SawyerTaskConfig DoorClose::Config() {
  SawyerTaskConfig config =
      door::DoorConfig("door-close", "Sawyer arm: swing an open door shut", "door_close.xml",
                       {-0.5, 0.6, 0.2}, kGoalOffset);
  // v3's goal_space: the goals' box with z widened 0.1 mm either way.
  config.goal_space = Range3{{0.2, 0.65, 0.1499}, {0.3, 0.75, 0.1501}};
  return config;
}

DoorClose::DoorClose(SawyerOptions options)
    : ArticulatedTask(Config(), door::HingedDoor(kStartAngle, kGoalOffset), options) {}

RewardTerms DoorClose::ComputeReward(const SawyerState& s, std::span<const float>) const {
  constexpr double kTargetRadius = 0.05;
  const double obj_to_target = Distance(s.obj, s.goal);
  const double in_place =
      GaussianTolerance(obj_to_target, 0.0, kTargetRadius, Distance(s.obj_init, s.goal));
  const double hand_in_place = GaussianTolerance(Distance(s.tcp, s.goal), 0.0, 0.25 * kTargetRadius,
                                                 Distance(s.hand_init, s.obj) + 0.1);
  RewardTerms terms;
  terms.reward = obj_to_target < kTargetRadius ? 10.0 : 3.0 * hand_in_place + 6.0 * in_place;
  terms.success = obj_to_target <= kSuccess;
  terms.near_object = 0.0;
  terms.grasp_success = 1.0;
  terms.grasp_reward = 1.0;
  terms.in_place_reward = hand_in_place;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void DoorClose::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  // v3: the handle's xy distance to the goal with the door open at reset
  s.v1_max_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
}

RewardTerms DoorClose::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double pull_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  RewardTerms terms;
  terms.reward = v1::ReachThenProgress(Distance(s.obj, s.tcp), s.v1_max_dist, pull_dist);
  // v3's evaluate_state on v1's (reward, pull_dist, 0)
  terms.success = pull_dist <= kSuccess;
  terms.grasp_success = 1.0;
  terms.grasp_reward = 1.0;
  terms.obj_to_target = pull_dist;
  return terms;
}

void DoorCloseScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 obj{o.goal[0] - kGoalOffset[0], o.goal[1] - kGoalOffset[1],
                 o.goal[2] - kGoalOffset[2]};
  PushPanel(o, door::Hinge(obj), door::HingeAngle(o.obj1, obj), kShut, 0.2,
            door::kPushHeight, door::kClearHeight, action);
}

}  // namespace manyworlds::manipulation
