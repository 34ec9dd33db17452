#include "manyworlds/manipulation/door/door_open.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "manyworlds/manipulation/door/door_fixture.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{-0.3, -0.45, 0.0};
constexpr double kSuccessX = 0.08;
// Turn past the goal (success comes between 1.38 and 1.82 rad of hinge
// travel), short of the hinge's limit.
constexpr double kTurnTo = door::kMaxOpen - 0.2;

}  // namespace

SawyerTaskConfig DoorOpen::Config() {
  SawyerTaskConfig config = door::DoorConfig(
      "door-open", "Sawyer arm: swing a door open by its handle", "door_open.xml",
      {0.0, 0.6, 0.2}, kGoalOffset);
  // v3's goal_space: the goals' box with z widened 0.1 mm either way.
  config.goal_space = Range3{{-0.3, 0.4, 0.1499}, {-0.2, 0.5, 0.1501}};
  return config;
}

DoorOpen::DoorOpen(SawyerOptions options)
    : ArticulatedTask(Config(), door::HingedDoor(0.0, kGoalOffset), options) {}

RewardTerms DoorOpen::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const Vec3& hand = s.hand;
  const Vec3 door{s.obj[0] - 0.05, s.obj[1], s.obj[2]};
  // A funnel-shaped floor around the handle keeps the hand from reaching it
  // low, through the door.
  constexpr double kFunnel = 0.12;
  const double radius = std::hypot(hand[0] - door[0], hand[1] - door[1]);
  const double floor = radius <= kFunnel ? 0.0 : 0.04 * std::log(radius - kFunnel) + 0.4;
  const double above_floor =
      hand[2] >= floor ? 1.0 : LongTailTolerance(floor - hand[2], 0.0, 0.01, floor / 2.0);
  const Vec3 beside{s.obj[0], s.obj[1] + 0.03, s.obj[2] - 0.01};  // door + (0.05, 0.03, -0.01)
  const double in_place = LongTailTolerance(Distance(hand, beside), 0.0, kFunnel / 2.0, 0.5);
  const double ready = HamacherProduct(above_floor, in_place);

  const double theta = s.joint_qpos;
  const double opened =
      0.2 * (theta < -std::numbers::pi / 90.0 ? 1.0 : 0.0) +
      0.8 * LongTailTolerance(std::numbers::pi / 2.0 + std::numbers::pi / 6.0 + theta, 0.0, 0.5,
                              std::numbers::pi / 3.0);
  const double grab = GripEffort(action);
  const bool success = std::abs(s.obj[0] - s.goal[0]) <= kSuccessX;

  return GripRewardTerms(success ? 10.0 : 2.0 * HamacherProduct(ready, grab) + 8.0 * opened,
                         success, ready, grab, opened);
}

void DoorOpen::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  // v3: |handle geom - goal| in xy with the door closed; our object point
  // stands in for v3's handle geom (our handle is our own)
  s.v1_max_dist = std::hypot(s.obj_init[0] - s.goal[0], s.obj_init[1] - s.goal[1]);
}

RewardTerms DoorOpen::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double pull_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  const double reach_dist = Distance(s.obj, s.tcp);
  RewardTerms terms;
  terms.reward = v1::ReachThenProgress(reach_dist, s.v1_max_dist, pull_dist);
  // v3's evaluate_state on v1's (reward, 0, 0, 0): success as in v2
  terms.success = std::abs(s.obj[0] - s.goal[0]) <= kSuccessX;
  return terms;
}

void DoorOpenScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                 std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 obj{o.goal[0] - kGoalOffset[0], o.goal[1] - kGoalOffset[1],
                 o.goal[2] - kGoalOffset[2]};
  PushPanel(o, door::Hinge(obj), door::HingeAngle(o.obj1, obj), -kTurnTo, 0.25,
            door::kPushHeight, door::kClearHeight, action);
}

}  // namespace manyworlds::manipulation
