#include "manyworlds/manipulation/object_tasks.h"

#include <cmath>
#include <utility>

#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {

double CageObject(const SawyerState& s, const Vec3& obj, double gripper_action,
                  const CagingParams& params) {
  return GripperCagingReward(
      {s.left_pad, s.right_pad, s.tcp, obj, s.obj_init, s.tcp_init, gripper_action}, params);
}

double PadCagingY(const SawyerState& s, double low, double high) {
  constexpr double kPadMargin = 0.05;
  const double left = s.left_pad[1] - s.obj[1];
  const double right = s.obj[1] - s.right_pad[1];
  const double left_margin = std::abs(std::abs(s.obj[1] - s.left_pad[1]) - kPadMargin);
  const double right_margin = std::abs(std::abs(s.obj[1] - s.right_pad[1]) - kPadMargin);
  return HamacherProduct(LongTailTolerance(left, low, high, left_margin),
                         LongTailTolerance(right, low, high, right_margin));
}

double TcpCagingXz(const SawyerState& s, double radius) {
  const double now = std::hypot(s.tcp[0] - s.obj[0], s.tcp[2] - s.obj[2]);
  const double at_reset = std::hypot(s.obj_init[0] - s.tcp_init[0], s.obj_init[2] - s.tcp_init[2]);
  return LongTailTolerance(now, 0.0, radius, at_reset - radius);
}

double SweepCaging(const SawyerState& s, double obj_radius, double band, double xz_radius) {
  const double caging = HamacherProduct(PadCagingY(s, obj_radius, 0.05), TcpCagingXz(s, xz_radius));
  const double gripping = caging > 0.95 ? PadCagingY(s, obj_radius, obj_radius + band) : 0.0;
  return (caging + gripping) / 2.0;
}

bool HeldAndLifted(const SawyerState& s, double tcp_radius, double lift) {
  return Distance(s.tcp, s.obj) < tcp_radius && s.gripper_opening > 0 &&
         s.obj[2] - lift > s.obj_init[2];
}

double GraspSuccess(const SawyerState& s) {
  return s.touching_obj && s.gripper_opening > 0 && s.obj[2] - 0.02 > s.obj_init[2] ? 1.0 : 0.0;
}

double WeightedDistance(const Vec3& a, const Vec3& b, const Vec3& w) {
  double sum = 0;
  for (int i = 0; i < 3; ++i) sum += (w[i] * (a[i] - b[i])) * (w[i] * (a[i] - b[i]));
  return std::sqrt(sum);
}

double FunnelFloor(double radius, double threshold, double scale, double height) {
  return radius <= threshold ? 0.0 : scale * std::log(radius - threshold) + height;
}

double AboveFloor(double z, double floor, double margin) {
  return z >= floor ? 1.0 : LongTailTolerance(floor - z, 0.0, 0.01, margin);
}

Vec3 SitePosition(const mjData* d, int site) {
  const mjtNum* p = d->site_xpos + 3 * site;
  return {p[0], p[1], p[2]};
}

void PlaceFixture(mjModel* m, int body, const Vec3& pos) {
  for (int i = 0; i < 3; ++i) m->body_pos[3 * body + i] = pos[i];
}

ShoulderReach ReachWithShoulder(const SawyerState& s, const Vec3& obj_at_reset,
                                const Vec3& scale) {
  constexpr Vec3 kShoulder{0.0, 0.055, 0.07};
  const Vec3 shoulder{s.hand[0] + kShoulder[0], s.hand[1] + kShoulder[1], s.hand[2] + kShoulder[2]};
  const Vec3 shoulder_init{s.tcp_init[0] + kShoulder[0], s.tcp_init[1] + kShoulder[1],
                           s.tcp_init[2] + kShoulder[2]};
  ShoulderReach reach;
  reach.distance = WeightedDistance(shoulder, s.obj, scale);
  reach.ready = LongTailTolerance(reach.distance, 0.0, 0.02,
                                  WeightedDistance(shoulder_init, obj_at_reset, scale));
  return reach;
}

double TowardGoal(const SawyerState& s, double obj_to_target, double radius) {
  return LongTailTolerance(obj_to_target, 0.0, radius, Distance(s.obj_init, s.goal));
}

bool OpenAndLifted(const SawyerState& s) {
  return s.gripper_opening > 0 && s.obj[2] - 0.03 > s.obj_init[2];
}

RewardTerms ObjectRewardTerms(const SawyerState& s, const ObjectReward& parts) {
  RewardTerms terms;
  terms.reward = parts.at_target ? 10.0 : parts.reward;
  terms.success = parts.obj_to_target <= parts.success_radius;
  terms.near_object = parts.tcp_to_obj <= parts.near_radius ? 1.0 : 0.0;
  terms.grasp_success = parts.grasp_success.value_or(GraspSuccess(s));
  terms.grasp_reward = parts.grasped;
  terms.in_place_reward = parts.in_place;
  terms.obj_to_target = parts.obj_to_target;
  return terms;
}

RewardTerms GripRewardTerms(double reward, bool success, double near_object, double grab,
                            double in_place) {
  RewardTerms terms;
  terms.reward = reward;
  terms.success = success;
  terms.near_object = near_object;
  terms.grasp_success = grab >= 0.5 ? 1.0 : 0.0;
  terms.grasp_reward = grab;
  terms.in_place_reward = in_place;
  terms.obj_to_target = 0.0;
  return terms;
}

GoalFixtureTask::GoalFixtureTask(SawyerTaskConfig config, const char* fixture_body,
                                 const Vec3& goal_on_fixture, SawyerOptions options)
    : SawyerTask(std::move(config), options), goal_on_fixture_(goal_on_fixture) {
  fixture_ = sim::IdLookup(model(), this->config().xml_file).Body(fixture_body);
}

void GoalFixtureTask::PlaceObjects(mjModel* m, mjData* d) {
  SawyerTask::PlaceObjects(m, d);
  const Vec3& goal = goal_pos();
  PlaceFixture(m, fixture_,
               {goal[0] - goal_on_fixture_[0], goal[1] - goal_on_fixture_[1],
                goal[2] - goal_on_fixture_[2]});
}

}  // namespace manyworlds::manipulation
