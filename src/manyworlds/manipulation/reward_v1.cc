#include "manyworlds/manipulation/reward_v1.h"

#include <algorithm>
#include <cmath>

namespace manyworlds::manipulation::v1 {

double Progress(double max_dist, double d) {
  return 1000.0 * (max_dist - d) + 1000.0 * (std::exp(-d * d / 0.01) + std::exp(-d * d / 0.001));
}

double ReachThenProgress(double reach_dist, double max_dist, double d, bool clamp) {
  if (reach_dist >= 0.05) return -reach_dist;
  const double bonus = Progress(max_dist, d);
  return -reach_dist + (clamp ? std::max(bonus, 0.0) : bonus);
}

double Reach(const SawyerState& s, const Vec3& point, double gripper_action, double xy_radius,
             double z_weight, double grip_radius) {
  const double dist = Distance(point, s.tcp);
  if (dist < grip_radius) return -dist + std::max(gripper_action, 0.0) / 50.0;
  const double xy = std::hypot(point[0] - s.tcp[0], point[1] - s.tcp[1]);
  return xy < xy_radius ? -dist : -xy - z_weight * std::abs(s.tcp[2] - s.tcp_init[2]);
}

bool Dropped(const SawyerState& s, double obj_z, double place_dist, double reach_dist) {
  return obj_z < s.v1_obj_height + 0.005 && place_dist > 0.02 && reach_dist > 0.02;
}

double LiftBonus(const SawyerState& s, double obj_z, bool held, bool near, double floor) {
  if (held) return 100.0 * (s.v1_height_target - floor);
  if (near && obj_z > s.v1_obj_height + 0.005) {
    return 100.0 * (std::min(s.v1_height_target, obj_z) - floor);
  }
  return 0.0;
}

double PickPlace(const SawyerState& s, double gripper_action, double place_dist,
                 double progress_dist, double z_weight, bool lift_from_start) {
  const double reach_dist = Distance(s.obj, s.tcp);
  const double reach = Reach(s, s.obj, gripper_action, 0.05, z_weight, 0.05);
  const bool picked = s.obj[2] >= s.v1_height_target - 0.01;
  const bool dropped = Dropped(s, s.obj[2], place_dist, reach_dist);
  const double pick = LiftBonus(s, s.obj[2], picked && !dropped, reach_dist < 0.1,
                                lift_from_start ? s.v1_obj_height - 0.02 : 0.0);
  double place = 0;
  if (picked && reach_dist < 0.1 && !dropped) {
    place = std::max(Progress(s.v1_max_dist, progress_dist), 0.0);
  }
  return reach + pick + place;
}

RewardTerms PickPlaceStep(const SawyerState& s, double gripper_action, double success_radius,
                          bool lift_from_start) {
  const double obj_to_target = Distance(s.obj, s.goal);
  return StepTerms(
      PickPlace(s, gripper_action, obj_to_target, obj_to_target, 2.0, lift_from_start),
      obj_to_target, success_radius);
}

RewardTerms StepTerms(double reward, double obj_to_target, double success_radius,
                      double grasp_success) {
  RewardTerms terms;
  terms.reward = reward;
  terms.success = obj_to_target <= success_radius;
  terms.near_object = 1.0;
  terms.grasp_success = grasp_success;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void InitPickPlace(SawyerState& s, double obj_height, double lift) {
  s.v1_obj_height = obj_height;
  s.v1_height_target = obj_height + lift;
  const Vec3 lifted{s.obj_init[0], s.obj_init[1], s.v1_height_target};
  s.v1_max_dist = Distance(lifted, s.goal) + s.v1_height_target;
}

RewardTerms ReachThenProgressStep(const SawyerState& s, double reach_dist, double dist,
                                  double success_radius, double grasp_success, bool clamp) {
  return StepTerms(ReachThenProgress(reach_dist, s.v1_max_dist, dist, clamp), dist,
                   success_radius, grasp_success);
}

RewardTerms PushStep(const SawyerState& s, double success_radius) {
  const double push_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  return ReachThenProgressStep(s, Distance(s.obj, s.tcp), push_dist, success_radius);
}

void InitPush(SawyerState& s) {
  s.v1_max_dist = std::hypot(s.obj_init[0] - s.goal[0], s.obj_init[1] - s.goal[1]);
}

}  // namespace manyworlds::manipulation::v1
