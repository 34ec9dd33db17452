#include "manyworlds/manipulation/articulated.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

// Grasping a handle (GraspAndMove).
constexpr double kHeldDistance = 0.025;  // tcp-grasp point distance while held
// Opening below this with the tcp at the handle: closed on it. Open is 1
// (0.8 at approach_grip -0.5); closed on the handles 0.26 to 0.4.
constexpr double kClosedOnHandle = 0.55;
constexpr double kAlignedXy = 0.01;  // xy error before descending
constexpr double kAtGraspHeight = 0.006;

// Pushing a bar with one pad (PushBarAlongX). The open +y pad's centre is
// 0.05 m from the hand in y; its side is 0.012 m from its centre in x.
constexpr double kPadY = 0.05;
constexpr double kPadContactX = 0.022;  // pad half-width + bar radius
constexpr double kReadyX = 0.03;        // hand behind the bar before the push
constexpr double kStageY = 0.04;        // in front of the ready point
// The tcp 1.5 cm above the bar's middle: the pad still covers the bar and
// the palm, which overhangs the pad in x, passes over the bar's top.
constexpr double kPushAbove = 0.015;

int Next(int axis) { return (axis + 1) % 3; }

}  // namespace

void UseGoalOffset(const Vec3& goal_offset, SawyerTaskConfig& config) {
  for (int i = 0; i < 3; ++i) {
    config.goal_low[i] = config.obj_low[i] + goal_offset[i];
    config.goal_high[i] = config.obj_high[i] + goal_offset[i];
  }
  config.min_obj_goal_xy = 0.0;
  config.goal_z_at_object = false;
}

ArticulatedTask::ArticulatedTask(SawyerTaskConfig config, FixtureSpec fixture,
                                 SawyerOptions options)
    : SawyerTask(std::move(config), options), fixture_(std::move(fixture)) {
  const sim::IdLookup ids(model(), this->config().xml_file);
  root_body_ = ids.Body(fixture_.root_body);
  joint_qpos_ = ids.QposAddress(fixture_.joint);
  joint_dof_ = ids.DofAddress(fixture_.joint);
}

Vec3 ArticulatedTask::DeriveGoal(const Vec3& obj, const Vec3&) const {
  return {obj[0] + fixture_.goal_offset[0], obj[1] + fixture_.goal_offset[1],
          obj[2] + fixture_.goal_offset[2]};
}

void ArticulatedTask::PlaceObjects(mjModel* m, mjData* d) {
  for (int i = 0; i < 3; ++i) {
    m->body_pos[3 * root_body_ + i] = obj_pos()[i] + fixture_.root_offset[i];
  }
  d->qpos[joint_qpos_] = fixture_.joint_init;
  d->qvel[joint_dof_] = 0;
  d->qacc_warmstart[joint_dof_] = 0;
}

void ArticulatedTask::DoReset(const ObsView& out) {
  SawyerTask::DoReset(out);
  handle_init_ = state().obj;
}

double ArticulatedTask::joint_pos() const { return data()->qpos[joint_qpos_]; }

double GripEffort(std::span<const float> action) {
  return (std::clamp(static_cast<double>(action[3]), -1.0, 1.0) + 1.0) / 2.0;
}

double FingerDistance(const SawyerState& s, const Vec3& point) {
  return std::min(
      {Distance(s.tcp, point), Distance(s.left_pad, point), Distance(s.right_pad, point)});
}

RewardTerms FixtureReward(double engaged, double in_place, bool success) {
  RewardTerms terms;
  terms.reward = success ? 10.0 : std::clamp(2.0 * engaged + 8.0 * in_place, 0.0, 10.0);
  terms.success = success;
  terms.grasp_reward = engaged;
  terms.in_place_reward = in_place;
  return terms;
}

RewardTerms MoveHandleReward(const SawyerState& s, const Vec3& handle_init, double radius) {
  const double finger_to_handle = FingerDistance(s, s.obj);
  const double obj_to_target = Distance(s.obj, s.goal);
  const double reach =
      LongTailTolerance(finger_to_handle, 0.0, 0.02, Distance(s.tcp_init, handle_init));
  const double in_place =
      LongTailTolerance(obj_to_target, 0.0, radius, Distance(handle_init, s.goal));
  RewardTerms terms = FixtureReward(reach, in_place, obj_to_target <= radius);
  terms.near_object = finger_to_handle <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = s.touching_obj ? 1.0 : 0.0;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void GraspAndMove(const SawyerObs& o, const Vec3& grasp, const Vec3& move_to, double approach_grip,
                  std::span<float> action, double carry_speed, double approach_height) {
  const auto hand_for_tcp = [](const Vec3& tcp) {
    return Vec3{tcp[0], tcp[1], tcp[2] + kTcpBelowHand};
  };
  if (Distance(o.tcp, grasp) < kHeldDistance && o.gripper_opening < kClosedOnHandle) {
    MoveTo(o.hand, hand_for_tcp(move_to), 1.0, action);
    const float limit = static_cast<float>(carry_speed);
    for (int i = 0; i < 3; ++i) action[i] = std::clamp(action[i], -limit, limit);
    return;
  }
  const double xy_error = std::hypot(o.tcp[0] - grasp[0], o.tcp[1] - grasp[1]);
  const double height = o.tcp[2] - grasp[2];
  // Slightly off while already low: correct on the way down rather than
  // climbing back up.
  if (xy_error > 2 * kAlignedXy || (xy_error > kAlignedXy && height > 0.5 * approach_height)) {
    MoveTo(o.hand, hand_for_tcp({grasp[0], grasp[1], grasp[2] + approach_height}), approach_grip,
           action);
  } else if (height > kAtGraspHeight) {
    MoveTo(o.hand, hand_for_tcp(grasp), approach_grip, action);
  } else {
    MoveTo(o.hand, hand_for_tcp(grasp), 1.0, action);
  }
}

Vec3 TurnAbout(const Vec3& p, const Vec3& center, int axis, double angle) {
  const int u = Next(axis), v = Next(u);
  const double du = p[u] - center[u], dv = p[v] - center[v];
  const double c = std::cos(angle), s = std::sin(angle);
  Vec3 out = p;
  out[u] = center[u] + c * du - s * dv;
  out[v] = center[v] + s * du + c * dv;
  return out;
}

double AngleAbout(const Vec3& p, const Vec3& center, int axis) {
  const int u = Next(axis), v = Next(u);
  return std::atan2(p[v] - center[v], p[u] - center[u]);
}

Vec3 NextPointOnArc(const Vec3& grasp, const Vec3& center, int axis, double target_angle,
                    double max_step) {
  const double to_go =
      std::remainder(target_angle - AngleAbout(grasp, center, axis), 2 * std::numbers::pi);
  return TurnAbout(grasp, center, axis, std::clamp(to_go, -max_step, max_step));
}

void PushBarAlongX(const SawyerObs& o, const Vec3& bar, double target_x, std::span<float> action) {
  const double dir = target_x > bar[0] ? 1.0 : -1.0;
  const Vec3 ready{bar[0] - dir * kReadyX, bar[1] - kPadY, bar[2] + kPushAbove + kTcpBelowHand};
  const double behind = dir * (bar[0] - o.hand[0]);  // > 0: on the pushing side
  const bool level = std::abs(o.hand[2] - ready[2]) < 0.015;
  const bool in_line = std::abs(o.hand[1] - ready[1]) < 0.01;
  if (level && in_line && behind > 0.015 && behind < 0.045) {
    // Sweep so that the bar ends 1 cm past the target.
    MoveTo(o.hand, {target_x - dir * (kPadContactX - 0.01), ready[1], ready[2]}, -1.0, action);
  } else if (level && std::abs(o.hand[0] - ready[0]) < 0.01) {
    MoveTo(o.hand, ready, -1.0, action);  // slide the pad in beside the bar
  } else {
    MoveTo(o.hand, {ready[0], std::min(o.hand[1], ready[1] - kStageY), ready[2]}, -1.0, action);
  }
}

}  // namespace manyworlds::manipulation
