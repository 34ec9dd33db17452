#include "manyworlds/manipulation/button/buttons.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{0.0, -0.1, 0.0};
constexpr Vec3 kBoxOffset{0.0, 0.0, -0.115};  // the box stands on the table
// v3's press margin: from its button-start site, 0.5 mm in front of the
// cap's face at rest, to the goal.
constexpr double kObjToTargetInit = 0.0935;

// Policy: the tcp 1 cm above the cap's centre (the palm, 3 cm above the tcp,
// then clears the housing and a wall's top), stopping 2.2 cm in front of
// the face before the push, and pushing toward a point 1.5 cm past the face
// (always ahead of the cap, so it goes in to its stop; the goal is not read,
// so the policy also works with the goal hidden).
constexpr double kPressAbove = 0.01;
constexpr double kStandOff = 0.022;
constexpr double kPushPast = 0.015;

FixtureSpec Fixture() { return {"button_box", kBoxOffset, "button_slide", 0.0, kGoalOffset}; }

// The shared pieces of both front-button rewards.
struct FrontTerms {
  double tcp_to_obj, tcp_to_obj_init, obj_to_target, pressed;
};

FrontTerms Front(const SawyerState& s) {
  FrontTerms t;
  t.tcp_to_obj = Distance(s.obj, s.tcp);
  t.tcp_to_obj_init = Distance(s.obj, s.tcp_init);
  t.obj_to_target = std::abs(s.goal[1] - s.obj[1]);
  t.pressed = LongTailTolerance(t.obj_to_target, 0.0, 0.005, s.obj_to_target_init);
  return t;
}

RewardTerms FrontRewardTerms(const SawyerState& s, const FrontTerms& t, double reward, double near,
                             double success_radius) {
  return PressRewardTerms(s, {.reward = reward, .obj_to_target = t.obj_to_target,
                              .success_radius = success_radius, .tcp_to_obj = t.tcp_to_obj,
                              .near = near, .pressed = t.pressed});
}

}  // namespace

SawyerTaskConfig FrontButtonTask::Config(std::string id, std::string description,
                                         std::string xml_file, Vec3 obj_low, Vec3 obj_high) {
  SawyerTaskConfig config;
  config.id = std::move(id);
  config.description = std::move(description);
  config.xml_file = std::move(xml_file);
  config.hand_init = {0.0, 0.4, 0.2};
  config.obj_low = obj_low;
  config.obj_high = obj_high;
  config.obj_quat = QuatLayout::kWxyz;
  UseGoalOffset(kGoalOffset, config);
  config.goal_space = Range3{config.hand_low, config.hand_high};  // v3's: the hand's range
  return config;
}

FrontButtonTask::FrontButtonTask(SawyerTaskConfig config, SawyerOptions options)
    : ArticulatedTask(std::move(config), Fixture(), options) {}

void FrontButtonTask::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.obj_to_target_init = kObjToTargetInit;
}

// The left finger's tip (not the tcp) reaches the button.
RewardTerms FrontButtonRewardV1(const SawyerState& s, double success_radius) {
  return v1::ReachThenProgressStep(s, Distance(s.obj, s.left_finger),
                                   std::abs(s.obj[1] - s.goal[1]), success_radius);
}

SawyerTaskConfig ButtonPress::Config() {
  return FrontButtonTask::Config("button-press", "Sawyer arm: push a button on the front of a box",
                                 "button_press.xml", {-0.1, 0.85, 0.115}, {0.1, 0.9, 0.115});
}

ButtonPress::ButtonPress(SawyerOptions options) : FrontButtonTask(Config(), options) {}

RewardTerms ButtonPress::ComputeReward(const SawyerState& s, std::span<const float>) const {
  return ButtonPressReward(s);
}

void ButtonPress::InitTaskState(SawyerState& s) const {
  FrontButtonTask::InitTaskState(s);
  s.v1_max_dist = s.obj_to_target_init;  // v3's maxDist: |buttonStart.y - goal.y|, the same
}

RewardTerms ButtonPress::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return FrontButtonRewardV1(s, 0.02);
}

RewardTerms ButtonPressReward(const SawyerState& s) {
  const FrontTerms t = Front(s);
  const double near = LongTailTolerance(t.tcp_to_obj, 0.0, 0.05, t.tcp_to_obj_init);
  double reward = 2.0 * HamacherProduct(std::max(s.gripper_opening, 0.0), near);
  if (t.tcp_to_obj <= 0.05) reward += 8.0 * t.pressed;
  return FrontRewardTerms(s, t, reward, near, 0.02);
}

SawyerTaskConfig ButtonPressWall::Config() {
  return FrontButtonTask::Config(
      "button-press-wall", "Sawyer arm: push a button on the front of a box behind a wall",
      "button_press_wall.xml", {-0.05, 0.85, 0.1149}, {0.05, 0.9, 0.1151});
}

ButtonPressWall::ButtonPressWall(SawyerOptions options) : FrontButtonTask(Config(), options) {}

void ButtonPressWall::InitTaskState(SawyerState& s) const {
  FrontButtonTask::InitTaskState(s);
  // v3's maxDist here compares heights, not the press direction (0 on its table)
  s.v1_max_dist = std::abs(s.obj[2] - s.goal[2]);
}

RewardTerms ButtonPressWall::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return FrontButtonRewardV1(s, 0.03);
}

RewardTerms ButtonPressWall::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const FrontTerms t = Front(s);
  const double near = LongTailTolerance(t.tcp_to_obj, 0.0, 0.01, t.tcp_to_obj_init);
  const double reward =
      t.tcp_to_obj > 0.07
          ? 2.0 * HamacherProduct((1.0 - s.gripper_opening) / 2.0, near)
          : 2.0 + 2.0 * (1.0 + s.gripper_opening) + 4.0 * t.pressed * t.pressed;
  return FrontRewardTerms(s, t, reward, near, 0.03);
}

SawyerTaskConfig ButtonPressTopdownWall::Config() {
  SawyerTaskConfig config = ButtonPressTopdown::Config();
  config.id = "button-press-topdown-wall";
  config.description = "Sawyer arm: press a button on top of a box behind a wall";
  config.xml_file = "button_press_topdown_wall.xml";
  return config;
}

ButtonPressTopdownWall::ButtonPressTopdownWall(SawyerOptions options)
    : ButtonPressTopdown(Config(), options) {}

RewardTerms ButtonPressTopdownWall::ComputeReward(const SawyerState& s,
                                                  std::span<const float> action) const {
  RewardTerms terms = ButtonPressTopdown::ComputeReward(s, action);
  // Only the gripper term differs: max(obs[3], 0) for 1 - obs[3].
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  terms.reward = 5.0 * HamacherProduct(std::max(s.gripper_opening, 0.0), terms.grasp_reward);
  if (tcp_to_obj <= 0.03) terms.reward += 5.0 * terms.in_place_reward;
  return terms;
}

void FrontButtonScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                    std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3& face = o.obj1;
  const double press_z = face[2] + kPressAbove;
  const double stand_y = face[1] - kStandOff;
  const auto hand_for = [](double x, double y, double z) { return Vec3{x, y, z + kTcpBelowHand}; };
  const double x_error = std::abs(o.tcp[0] - face[0]);
  const double z_error = std::abs(o.tcp[2] - press_z);
  // Lined up in x and at or past the stand-off point in y.
  const bool in_front = x_error < 0.015 && o.tcp[1] > stand_y - 0.015;
  Vec3 target;
  if (in_front && z_error < 0.008) {
    target = hand_for(face[0], face[1] + kPushPast, press_z);  // push to the stop
  } else if (in_front || clear_height_ <= 0) {
    target = hand_for(face[0], std::max(o.tcp[1], stand_y), press_z);  // line up in front
  } else {
    target = hand_for(face[0], stand_y, clear_height_);  // over the wall
  }
  MoveTo(o.hand, target, 1.0, action);
}

}  // namespace manyworlds::manipulation
