#include "manyworlds/manipulation/window/window.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

// The shut bar's x relative to the goal.
constexpr double kBarX = 0.014;
constexpr double kTargetRadius = 0.05;  // v3's TARGET_RADIUS

// What differs between the two directions.
struct WindowSpec {
  const char* id;
  const char* description;
  const char* xml_file;
  Vec3 obj_low, obj_high;
  Vec3 goal_offset;   // goal = obj_pos + this (v3's window body, moved)
  double start_open;  // the sash's slide at reset
  // The frame (root body) stands on the table with the shut handle bar at
  // obj_pos + (-0.014, -0.095, 0), obj_pos z up.
  Vec3 frame_offset;
  double bar_from_point;  // the handle bar's x relative to the object point
  // in_place's margin from handle_init (else obj_init); reach gaussian
  // (else long-tail): as v3's window-close.
  bool close;
};

const WindowSpec& Spec(WindowMotion motion) {
  static const WindowSpec kOpen{"window-open",
                                "Sawyer arm: slide a window open by its handle",
                                "window_open.xml",
                                {-0.1, 0.7, 0.16},
                                {0.1, 0.9, 0.16},
                                {0.2, 0.0, 0.0},
                                0.0,
                                {-0.014, -0.095, -0.16},
                                0.026,
                                false};
  static const WindowSpec kClose{"window-close",
                                 "Sawyer arm: slide an open window shut by its handle",
                                 "window_close.xml",
                                 {0.0, 0.75, 0.2},
                                 {0.0, 0.9, 0.2},
                                 {0.0, 0.0, 0.0},
                                 0.2,
                                 {-0.014, -0.095, -0.2},
                                 -0.024,
                                 true};
  return motion == WindowMotion::kOpen ? kOpen : kClose;
}

FixtureSpec Fixture(const WindowSpec& spec) {
  return {"window_frame", spec.frame_offset, "window_slide", spec.start_open, spec.goal_offset};
}

}  // namespace

SawyerTaskConfig Window::Config(WindowMotion motion) {
  const WindowSpec& spec = Spec(motion);
  SawyerTaskConfig config;
  config.id = spec.id;
  config.description = spec.description;
  config.xml_file = spec.xml_file;
  config.hand_init = {0.0, 0.4, 0.2};
  config.obj_low = spec.obj_low;
  config.obj_high = spec.obj_high;
  config.obj_quat = QuatLayout::kZeros;
  UseGoalOffset(spec.goal_offset, config);
  config.goal_space = Range3{config.hand_low, config.hand_high};  // v3's: the hand's range
  return config;
}

Window::Window(WindowMotion motion, SawyerOptions options)
    : ArticulatedTask(Config(motion), Fixture(Spec(motion)), options), motion_(motion) {}

RewardTerms Window::ComputeReward(const SawyerState& s, std::span<const float>) const {
  constexpr double kHandleRadius = 0.02;
  const bool close = Spec(motion_).close;
  const double target_to_obj = std::abs(s.obj[0] - s.goal[0]);
  const double start_x = close ? s.handle_init[0] : s.obj_init[0];
  const double in_place =
      LongTailTolerance(target_to_obj, 0.0, kTargetRadius,
                        std::abs(std::abs(start_x - s.goal[0]) - kTargetRadius));
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  const double reach_margin = std::abs(Distance(s.handle_init, s.tcp_init) - kHandleRadius);
  const double reach = close ? GaussianTolerance(tcp_to_obj, 0.0, kHandleRadius, reach_margin)
                             : LongTailTolerance(tcp_to_obj, 0.0, kHandleRadius, reach_margin);
  return ReachAndMoveTerms({.reach = reach, .in_place = in_place, .obj_to_target = target_to_obj,
                            .success = target_to_obj <= kTargetRadius,
                            .near = tcp_to_obj <= 0.05});
}

void Window::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.v1_max_dist = 0.2;  // v3's maxPullDist, a constant
}

RewardTerms Window::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  // v3 does not clamp this bonus at 0
  return v1::ReachThenProgressStep(s, Distance(s.obj, s.tcp), std::abs(s.obj[0] - s.goal[0]),
                                   kTargetRadius, /*grasp_success=*/1.0, /*clamp=*/false);
}

void WindowScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                               std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 bar{o.obj1[0] + Spec(motion_).bar_from_point, o.obj1[1], o.obj1[2]};
  // To the stop (open) or the shut position (close): the bar 0.014 m short
  // of the goal in x.
  PushBarAlongX(o, bar, o.goal[0] - kBarX, action);
}

}  // namespace manyworlds::manipulation
