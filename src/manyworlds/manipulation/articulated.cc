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

// Pushing a panel (PushPanel): the tcp's distance from the panel's middle
// plane while the closed fingers touch its face (finger half-width 0.012,
// panel half-thickness 0.01, a little play), and the angle the push aims
// ahead of the panel.
constexpr double kPanelStandOff = 0.025;
constexpr double kPanelStep = 0.3;

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
  const mjModel* m = model();
  obj_body_ = ids.Body("obj");
  for (int i = 0; i < 3; ++i) {
    obj_pos0_[i] = m->body_pos[3 * obj_body_ + i];
    obj_ipos0_[i] = m->body_ipos[3 * obj_body_ + i];
  }
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] == obj_body_) {
      obj_geom_pos0_.push_back({g, {m->geom_pos[3 * g], m->geom_pos[3 * g + 1], m->geom_pos[3 * g + 2]}});
    }
  }
}

Vec3 ArticulatedTask::DeriveGoal(const Vec3& obj, const Vec3&) const {
  return {obj[0] + fixture_.goal_offset[0], obj[1] + fixture_.goal_offset[1],
          obj[2] + fixture_.goal_offset[2]};
}

void ArticulatedTask::PlaceObjects(mjModel* m, mjData* d) {
  for (int i = 0; i < 3; ++i) {
    m->body_pos[3 * root_body_ + i] = obj_pos()[i] + fixture_.root_offset[i];
  }
  // Assigned from the model file's values, so repeated resets (and the
  // copies SaveVariationXml makes) shift once.
  const Vec3& shift = fixture_.obj_origin_shift;
  for (int i = 0; i < 3; ++i) {
    m->body_pos[3 * obj_body_ + i] = obj_pos0_[i] + shift[i];
    m->body_ipos[3 * obj_body_ + i] = obj_ipos0_[i] - shift[i];
    for (const auto& [geom, pos0] : obj_geom_pos0_) m->geom_pos[3 * geom + i] = pos0[i] - shift[i];
  }
  d->qpos[joint_qpos_] = fixture_.joint_init;
  d->qvel[joint_dof_] = 0;
  d->qacc_warmstart[joint_dof_] = 0;
}

void ArticulatedTask::RefreshTaskState(const mjData* d, SawyerState& state) const {
  state.joint_qpos = fixture_.joint_qpos_sign * d->qpos[joint_qpos_];
}

void ArticulatedTask::InitTaskState(SawyerState& state) const {
  state.handle_init = state.obj;
  if (fixture_.obj_init_is_object_point) state.obj_init = state.obj;
}

double GripEffort(std::span<const float> action) {
  return (std::clamp(static_cast<double>(action[3]), -1.0, 1.0) + 1.0) / 2.0;
}

RewardTerms PressRewardTerms(const SawyerState& s, const PressReward& parts) {
  RewardTerms terms;
  terms.reward = parts.reward;
  terms.success = parts.obj_to_target <= parts.success_radius;
  terms.near_object = parts.tcp_to_obj <= 0.05 ? 1.0 : 0.0;
  terms.grasp_success = s.gripper_opening > 0 ? 1.0 : 0.0;
  terms.grasp_reward = parts.near;
  terms.in_place_reward = parts.pressed;
  terms.obj_to_target = parts.obj_to_target;
  return terms;
}

RewardTerms ReachAndMoveTerms(const ReachAndMove& parts) {
  RewardTerms terms;
  terms.reward = 10.0 * (parts.ten_at_success && parts.success
                             ? 1.0
                             : HamacherProduct(parts.reach, parts.in_place));
  terms.success = parts.success;
  terms.near_object = parts.near ? 1.0 : 0.0;
  terms.grasp_success = 1.0;
  terms.grasp_reward = parts.reach;
  terms.in_place_reward = parts.in_place;
  terms.obj_to_target = parts.obj_to_target;
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

void PushPanel(const SawyerObs& o, const Vec3& hinge, double angle, double target_angle,
               double push_at, double height, double clear_height, std::span<float> action) {
  // side = +1: the panel turns clockwise (seen from above), so it is pushed
  // on its face toward n = (-sin, cos) of its direction.
  const double side = target_angle < angle ? 1.0 : -1.0;
  // The tcp target `out` metres from the panel's middle plane on the pushed
  // side, with the panel at angle a.
  const auto point = [&](double a, double out, double z) {
    return Vec3{hinge[0] + push_at * std::cos(a) - side * out * std::sin(a),
                hinge[1] + push_at * std::sin(a) + side * out * std::cos(a), z + kTcpBelowHand};
  };
  const double dx = o.tcp[0] - hinge[0], dy = o.tcp[1] - hinge[1];
  const double along = dx * std::cos(angle) + dy * std::sin(angle);
  const double out = side * (-dx * std::sin(angle) + dy * std::cos(angle));
  const Vec3 stage = point(angle, 1.5 * kPanelStandOff, height);
  if (std::abs(along - push_at) < 0.05 && std::abs(o.tcp[2] - height) < 0.02 && out > -0.005 &&
      out < 2.5 * kPanelStandOff) {
    // At the face: aim through it where it will be a little further on.
    const double step = std::clamp(target_angle - angle, -kPanelStep, kPanelStep);
    MoveTo(o.hand, point(angle + step, 0.0, height), 1.0, action);
  } else if (out > kPanelStandOff) {
    // On the pushed side: the straight way to the stage point stays clear of
    // the panel.
    MoveTo(o.hand, stage, 1.0, action);
  } else if (o.tcp[2] < clear_height) {
    MoveTo(o.hand, {o.hand[0], o.hand[1], clear_height + 0.03 + kTcpBelowHand}, 1.0, action);
  } else {
    MoveTo(o.hand, {stage[0], stage[1], clear_height + 0.03 + kTcpBelowHand}, 1.0, action);
  }
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
