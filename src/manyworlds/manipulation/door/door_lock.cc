#include "manyworlds/manipulation/door/door_lock.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "manyworlds/manipulation/door/door_fixture.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/manipulation/bar_push.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kLockAxis{0.0, -0.118, 0.061};  // from obj_pos
constexpr Vec3 kLockGoal{0.0, -0.158, -0.039};    // lock axis + (0, -0.04, -0.1)
constexpr Vec3 kUnlockGoal{0.1, -0.158, 0.061};   // lock axis + (0.1, -0.04, 0)
constexpr Vec3 kScale{0.25, 1.0, 0.5};
constexpr double kLockLength = 0.1;
constexpr double kSuccess = 0.02;
// v3's sites sit 1 cm to one side of the bar (in its turning plane).
constexpr double kSiteSide = 0.01;
constexpr double kSiteAlong = 0.09;

SawyerTaskConfig LockConfig(const char* id, const char* description, const Vec3& goal_offset) {
  SawyerTaskConfig config =
      TaskConfig(id, description, "door_lock.xml", {{-0.1, 0.8, 0.15}, {0.1, 0.85, 0.15}});
  config.hand_init = {0.0, 0.6, 0.2};
  config.hand_low = {-0.5, 0.4, -0.15};
  config.hand_high = {0.5, 1.0, 0.5};
  config.obj_quat = QuatLayout::kWxyz;
  config.obj_quat_body = "door";
  UseGoalOffset(goal_offset, config);
  return config;
}

FixtureSpec LockFixture(double joint_init, const Vec3& goal, double site_z) {
  FixtureSpec fixture{"door_frame", door::kFrameOffset, "lock_hinge", joint_init, goal};
  fixture.obj_origin_shift = {0.0, 0.0, site_z};
  return fixture;
}

// The bar's angle in the lock's turning plane, (z, x) about the y axis
// (rotary::BarPush with depth 1), from the object point: the site lies
// `site_angle` off the bar.
void PushLockBar(std::span<const float> env_obs, const Vec3& goal_offset, double site_angle,
                 int direction, std::span<float> action) {
  const SawyerObs o(env_obs);
  rotary::BarPush push;
  const Vec3 obj{o.goal[0] - goal_offset[0], o.goal[1] - goal_offset[1],
                 o.goal[2] - goal_offset[2]};
  push.center = {obj[0] + kLockAxis[0], obj[1] + kLockAxis[1], obj[2] + kLockAxis[2]};
  push.bar_angle =
      std::atan2(o.obj1[0] - push.center[0], o.obj1[2] - push.center[2]) + site_angle;
  push.direction = direction;
  push.push_at = 0.07;
  push.standoff = 0.03;
  push.depth = 1;
  push.height = push.center[1] - 0.024;  // the bar's middle in y
  push.clear = -0.07;                    // in front of the lock
  rotary::PushBarAround(o, push, action);
}

}  // namespace

DoorLockTask::DoorLockTask(SawyerTaskConfig config, FixtureSpec fixture, SawyerOptions options)
    : ArticulatedTask(std::move(config), std::move(fixture), options) {}

void DoorLockTask::InitTaskState(SawyerState& state) const {
  ArticulatedTask::InitTaskState(state);
  for (int i = 0; i < 3; ++i) state.obj_init[i] = obj_pos()[i] + kLockAxis[i];
  state.v1_max_dist = Distance(state.goal, state.obj_init);  // v3's maxPullDist
}

RewardTerms DoorLockTask::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return v1::ReachThenProgressStep(s, Distance(s.obj, s.tcp), Distance(s.obj, s.goal), kSuccess);
}

SawyerTaskConfig DoorLock::Config() {
  SawyerTaskConfig config =
      LockConfig("door-lock", "Sawyer arm: turn a door's lock down", kLockGoal);
  config.goal_space = Range3{config.hand_low, config.hand_high};  // v3's: the hand's range
  return config;
}

DoorLock::DoorLock(SawyerOptions options)
    : DoorLockTask(Config(), LockFixture(0.0, kLockGoal, kSiteSide), options) {}

RewardTerms DoorLock::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double tcp_to_obj = WeightedDistance(s.obj, s.left_pad, kScale);
  const double obj_to_target = std::abs(s.goal[2] - s.obj[2]);
  const double near_lock = LongTailTolerance(tcp_to_obj, 0.0, 0.01, tcp_to_obj);
  const double pressed = LongTailTolerance(obj_to_target, 0.0, 0.005, kLockLength);
  const double reward =
      2.0 * HamacherProduct(std::max(s.gripper_opening, 0.0), near_lock) + 8.0 * pressed;
  return PressRewardTerms(s, {.reward = reward, .obj_to_target = obj_to_target,
                              .success_radius = kSuccess, .tcp_to_obj = tcp_to_obj,
                              .near = near_lock, .pressed = pressed});
}

SawyerTaskConfig DoorUnlock::Config() {
  SawyerTaskConfig config =
      LockConfig("door-unlock", "Sawyer arm: turn a door's lock back up", kUnlockGoal);
  // v3's goal_space, up to 8 mm wider in y than where the goals lie.
  config.goal_space = Range3{{0.0, 0.64, 0.21}, {0.2, 0.7, 0.2111}};
  return config;
}

DoorUnlock::DoorUnlock(SawyerOptions options)
    : DoorLockTask(Config(), LockFixture(std::numbers::pi / 2, kUnlockGoal, -kSiteSide),
                   options) {}

RewardTerms DoorUnlock::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const ShoulderReach reach = ReachWithShoulder(s, s.obj_init, kScale);
  const double obj_to_target = std::abs(s.goal[0] - s.obj[0]);
  const double pushed = LongTailTolerance(obj_to_target, 0.0, 0.005, kLockLength);
  return PressRewardTerms(s, {.reward = 2.0 * reach.ready + 8.0 * pushed,
                              .obj_to_target = obj_to_target, .success_radius = kSuccess,
                              .tcp_to_obj = reach.distance, .near = reach.ready,
                              .pressed = pushed});
}

void DoorLockScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                 std::span<float> action) {
  // The lock site lies toward +z of the bar (angles atan2(x, z): less);
  // unlocking turns the other way.
  const int direction = unlock_ ? -1 : 1;
  PushLockBar(env_obs, unlock_ ? kUnlockGoal : kLockGoal,
              direction * std::atan2(kSiteSide, kSiteAlong), direction, action);
}

}  // namespace manyworlds::manipulation
