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

PickPlaceTerms PickPlace(const SawyerState& s, double gripper_action, double place_dist,
                         double progress_dist, double z_weight, bool lift_from_start) {
  const double reach_dist = Distance(s.obj, s.tcp);
  const double reach_xy = std::hypot(s.obj[0] - s.tcp[0], s.obj[1] - s.tcp[1]);
  const double z_rise = std::abs(s.tcp[2] - s.tcp_init[2]);
  double reach = reach_xy < 0.05 ? -reach_dist : -reach_xy - z_weight * z_rise;
  // v3: the finger-closing incentive replaces the reach term near the object
  if (reach_dist < 0.05) reach = -reach_dist + std::max(gripper_action, 0.0) / 50.0;

  const double height_target = s.v1_height_target;
  const bool picked = s.obj[2] >= height_target - 0.01;
  const bool dropped =
      s.obj[2] < s.v1_obj_height + 0.005 && place_dist > 0.02 && reach_dist > 0.02;
  const double floor = lift_from_start ? s.v1_obj_height - 0.02 : 0.0;
  double pick = 0;
  if (picked && !dropped) {
    pick = 100.0 * (height_target - floor);
  } else if (reach_dist < 0.1 && s.obj[2] > s.v1_obj_height + 0.005) {
    pick = 100.0 * (std::min(height_target, s.obj[2]) - floor);
  }
  double place = 0;
  if (picked && reach_dist < 0.1 && !dropped) {
    place = std::max(Progress(s.v1_max_dist, progress_dist), 0.0);
  }
  return {reach + pick + place, reach_dist, place_dist};
}

void InitPickPlace(SawyerState& s, double obj_height, double lift) {
  s.v1_obj_height = obj_height;
  s.v1_height_target = obj_height + lift;
  const Vec3 lifted{s.obj_init[0], s.obj_init[1], s.v1_height_target};
  s.v1_max_dist = Distance(lifted, s.goal) + s.v1_height_target;
}

}  // namespace manyworlds::manipulation::v1
