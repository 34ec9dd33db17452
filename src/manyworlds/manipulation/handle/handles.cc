#include "manyworlds/manipulation/handle/handles.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kPressRadius = 0.02;  // v3's TARGET_RADIUS of the press tasks
constexpr double kPullRadius = 0.05;   // and of the pull tasks
constexpr double kPressStart = -0.001;  // v3's joint at reset (press tasks)
constexpr double kPullStart = -0.1;     // the bottom of the travel (pull tasks)
// The press tasks' return spring: its rest point 1 cm above the top of the
// travel, so it holds the 50 g part up against the stop.
constexpr double kPressStiffness = 150.0;
// The press tasks' hand starts 2.5 cm above v3's (0, 0.6, 0.2): our open
// fingers reach 1.5 cm further below the hand than v3's, and at v3's start
// they would rest on the bar (its top 0.171 m up, under the hand in about
// half the variations) and press it before the episode begins.
constexpr Vec3 kPressHandInit{0.0, 0.6, 0.225};
constexpr double kPressSpringRef = 0.01;
// Body "obj"'s origin in the model files is the bar's top (handleStart);
// the pull tasks read other points of the moving part (post frame).
constexpr Vec3 kHandleRight{0.05, 0.0, -0.008};
constexpr Vec3 kHandleCenter{0.0, 0.046, -0.022};

SawyerTaskConfig Base(const char* id, const char* description, bool side) {
  SawyerTaskConfig config;
  config.id = id;
  config.description = description;
  config.xml_file = side ? "handle_press_side.xml" : "handle_press.xml";
  config.hand_init = {0.0, 0.6, 0.2};
  config.obj_quat = QuatLayout::kZeros;
  return config;
}

// v1's handle reward: the left finger's tip (not the tcp) reaches the handle.
RewardTerms HandleRewardV1(const SawyerState& s, double success_radius, double grasp_success) {
  return v1::ReachThenProgressStep(s, Distance(s.obj, s.left_finger),
                                   std::abs(s.obj[2] - s.goal[2]), success_radius, grasp_success);
}

Vec3 GoalOffset(bool side, double z) { return side ? Vec3{0.216, 0.0, z} : Vec3{0.0, -0.216, z}; }

FixtureSpec Fixture(bool side, double joint_init, double goal_z, Vec3 shift = {},
                    bool obj_init_is_point = false) {
  FixtureSpec f{"handle_box", {}, "handle_slide", joint_init, GoalOffset(side, goal_z)};
  f.obj_origin_shift = shift;
  f.obj_init_is_object_point = obj_init_is_point;
  return f;
}

CagingParams PullCaging(double radius, double pad_threshold) {
  return CagingParams{.obj_radius = radius,
                      .pad_success_thresh = pad_threshold,
                      .xz_thresh = 0.01,
                      .high_density = true};
}

// The pull reward around d (the task's distance to the goal) and its
// bonus test (v3's own, differing between the two tasks).
RewardTerms PullTerms(const SawyerState& s, std::span<const float> action, double d,
                      double d_init, const CagingParams& caging, bool bonus_ok,
                      double success_radius) {
  const double in_place = LongTailTolerance(d, 0.0, kPullRadius, d_init);
  const double grasped = CageObject(s, s.obj, action[3], caging);
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  double reward = HamacherProduct(grasped, in_place);
  if (tcp_to_obj < 0.035 && s.gripper_opening > 0 && bonus_ok) reward += 1.0 + 5.0 * in_place;
  return ObjectRewardTerms(s, {.reward = reward, .at_target = d < kPullRadius, .obj_to_target = d,
                               .success_radius = success_radius, .tcp_to_obj = tcp_to_obj,
                               .near_radius = 0.05, .grasped = grasped, .in_place = in_place,
                               .grasp_success = OpenAndLifted(s) ? 1.0 : 0.0});
}

}  // namespace

HandlePressTask::HandlePressTask(SawyerTaskConfig config, FixtureSpec fixture,
                                 SawyerOptions options)
    : ArticulatedTask(std::move(config), std::move(fixture), options) {
  const sim::IdLookup ids(model(), this->config().xml_file);
  joint_ = ids.Joint("handle_slide");
  qpos_ = ids.QposAddress("handle_slide");
}

void HandlePressTask::PlaceObjects(mjModel* m, mjData* d) {
  ArticulatedTask::PlaceObjects(m, d);
  m->jnt_stiffness[joint_] = kPressStiffness;
  m->qpos_spring[qpos_] = kPressSpringRef;
}

RewardTerms HandlePressTask::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double d = std::abs(s.obj[2] - s.goal[2]);
  const double d_init = std::abs(s.handle_init[2] - s.goal[2]);
  const double in_place = LongTailTolerance(d, 0.0, kPressRadius, std::abs(d_init - kPressRadius));
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  const double tcp_to_obj_init = Distance(s.handle_init, s.tcp_init);
  const double reach = LongTailTolerance(tcp_to_obj, 0.0, 0.02, std::abs(tcp_to_obj_init - 0.02));
  return ReachAndMoveTerms({.reach = reach, .in_place = in_place, .obj_to_target = d,
                            .success = d <= kPressRadius, .near = tcp_to_obj <= 0.05,
                            .ten_at_success = true});
}

void HandlePressTask::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.v1_max_dist = std::abs(s.obj[2] - s.goal[2]);  // v3's maxDist
}

RewardTerms HandlePressTask::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return HandleRewardV1(s, kPressRadius, 1.0);
}

SawyerTaskConfig HandlePress::Config() {
  SawyerTaskConfig config = Base("handle-press", "Sawyer arm: press a handle down", false);
  config.hand_init = kPressHandInit;
  config.obj_low = {-0.1, 0.8, -0.001};
  config.obj_high = {0.1, 0.9, 0.001};
  UseGoalOffset(GoalOffset(false, 0.075), config);
  // v3's goal_space, y 0.55-0.7 and z 0.04-0.08, wider than where the
  // goals lie, y 0.584-0.684 and z 0.074-0.076 (v3's and ours).
  config.goal_space = Range3{{-0.1, 0.55, 0.04}, {0.1, 0.7, 0.08}};
  return config;
}

HandlePress::HandlePress(SawyerOptions options)
    : HandlePressTask(Config(), Fixture(false, kPressStart, 0.075), options) {}

SawyerTaskConfig HandlePressSide::Config() {
  SawyerTaskConfig config =
      Base("handle-press-side", "Sawyer arm: press down a handle facing sideways", true);
  config.hand_init = kPressHandInit;
  config.obj_low = {-0.35, 0.65, -0.001};
  config.obj_high = {-0.25, 0.75, 0.001};
  UseGoalOffset(GoalOffset(true, 0.075), config);
  config.goal_space = Range3{config.hand_low, config.hand_high};  // v3's: the hand's range
  return config;
}

HandlePressSide::HandlePressSide(SawyerOptions options)
    : HandlePressTask(Config(), Fixture(true, kPressStart, 0.075), options) {}

SawyerTaskConfig HandlePull::Config() {
  SawyerTaskConfig config = Base("handle-pull", "Sawyer arm: pull a handle up", false);
  config.obj_low = {-0.1, 0.8, -0.001};
  config.obj_high = {0.1, 0.9, 0.001};
  UseGoalOffset(GoalOffset(false, 0.172), config);
  // v3's goal_space, y 0.55-0.7 and z 0.04-0.18, wider than where the
  // goals lie, y 0.584-0.684 and z 0.171-0.173 (v3's and ours).
  config.goal_space = Range3{{-0.1, 0.55, 0.04}, {0.1, 0.7, 0.18}};
  return config;
}

HandlePull::HandlePull(SawyerOptions options)
    : ArticulatedTask(Config(), Fixture(false, kPullStart, 0.172, kHandleRight), options) {}

RewardTerms HandlePull::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double d = std::abs(s.goal[2] - s.obj[2]);
  const double d_init = std::abs(s.goal[2] - s.obj_init[2]);
  // v3 compares the point's y with obj_init's z here: always true on its table.
  const bool bonus_ok = s.obj[1] - 0.01 > s.obj_init[2];
  return PullTerms(s, action, d, d_init, PullCaging(0.022, 0.05), bonus_ok, kPullRadius);
}

void HandlePull::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  // v3's maxDist reads handleStart's height in its body's frame (model.site pos)
  constexpr double kV3HandleSiteLocalZ = 0.022;
  s.v1_max_dist = std::abs(kV3HandleSiteLocalZ - s.goal[2]);
}

RewardTerms HandlePull::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return HandleRewardV1(s, kPullRadius, 0.0);
}

SawyerTaskConfig HandlePullSide::Config() {
  SawyerTaskConfig config =
      Base("handle-pull-side", "Sawyer arm: pull up a handle facing sideways", true);
  config.obj_low = {-0.35, 0.65, 0.0};
  config.obj_high = {-0.25, 0.75, 0.0};
  UseGoalOffset(GoalOffset(true, 0.172), config);
  config.goal_space = Range3{config.hand_low, config.hand_high};  // v3's: the hand's range
  return config;
}

HandlePullSide::HandlePullSide(SawyerOptions options)
    : ArticulatedTask(Config(), Fixture(true, kPullStart, 0.172, kHandleCenter, true), options) {}

RewardTerms HandlePullSide::ComputeReward(const SawyerState& s,
                                          std::span<const float> action) const {
  const double d = Distance(s.obj, s.goal);
  const double d_init = Distance(s.obj_init, s.goal);
  const bool bonus_ok = s.obj[2] - 0.01 > s.obj_init[2];
  return PullTerms(s, action, d, d_init, PullCaging(0.032, 0.06), bonus_ok, 0.08);
}

void HandlePressScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                    std::span<float> action) {
  constexpr double kHover = 0.05;      // tcp above the bar's top while aligning
  constexpr double kPadsBelow = 0.012;  // closed pads reach this far below the tcp
  const SawyerObs o(env_obs);
  const Vec3& top = o.obj1;
  const double xy_error = std::hypot(o.tcp[0] - top[0], o.tcp[1] - top[1]);
  const bool low = o.tcp[2] < top[2] + 0.6 * kHover;
  double tcp_z;
  if (xy_error > 0.015 || (xy_error > 0.008 && !low)) {
    tcp_z = std::max(o.tcp[2], top[2] + kHover);  // align first, never lower
  } else {
    tcp_z = top[2] + kPadsBelow - 0.03;  // always below the bar's top: down to the stop
  }
  MoveTo(o.hand, {top[0], top[1], tcp_z + kTcpBelowHand}, 1.0, action);
}

void HandlePullScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  constexpr double kApproach = 0.08;
  constexpr int kCloseSteps = 10;
  const SawyerObs o(env_obs);
  const Vec3 grasp{o.obj1[0] + grasp_offset_[0], o.obj1[1] + grasp_offset_[1],
                   o.obj1[2] + grasp_offset_[2]};
  const auto hand_for = [](double x, double y, double z) { return Vec3{x, y, z + kTcpBelowHand}; };
  if (closed_steps_ >= kCloseSteps) {
    MoveTo(o.hand, hand_for(grasp[0], grasp[1], grasp[2] + 0.1), 1.0, action);  // lift
    for (int i = 0; i < 3; ++i) action[i] = std::clamp(action[i], -0.5f, 0.5f);
    return;
  }
  const double xy_error = std::hypot(o.tcp[0] - grasp[0], o.tcp[1] - grasp[1]);
  const double height = o.tcp[2] - grasp[2];
  if (xy_error > 0.012 || (xy_error > 0.006 && height > 0.5 * kApproach)) {
    MoveTo(o.hand, hand_for(grasp[0], grasp[1], grasp[2] + kApproach), -1.0, action);
    closed_steps_ = 0;
  } else if (height > 0.006) {
    MoveTo(o.hand, hand_for(grasp[0], grasp[1], grasp[2]), -1.0, action);
  } else {
    MoveTo(o.hand, hand_for(grasp[0], grasp[1], grasp[2]), 1.0, action);
    ++closed_steps_;
  }
}

void HandlePullSide::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.v1_max_dist = std::abs(s.obj[2] - s.goal[2]);  // v3's maxDist
}

RewardTerms HandlePullSide::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return HandleRewardV1(s, 0.08, 0.0);
}

}  // namespace manyworlds::manipulation
