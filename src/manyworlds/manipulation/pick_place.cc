#include "manyworlds/manipulation/pick_place.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"

namespace manyworlds::manipulation {

SawyerTaskConfig PickPlace::Config() {
  SawyerTaskConfig config;
  config.id = "pick-place";
  config.description = "Sawyer arm: pick up a puck and place it at a goal in space";
  config.xml_file = "pick_place.xml";
  config.obj_low = {-0.1, 0.6, 0.02};
  config.obj_high = {0.1, 0.7, 0.02};
  config.goal_low = {-0.1, 0.8, 0.05};
  config.goal_high = {0.1, 0.9, 0.3};
  return config;
}

PickPlace::PickPlace(SawyerOptions options) : SawyerTask(Config(), options) {}

namespace {

// Meta-World v3's pick-place caging term (its own, not the shared one): the
// pads' signed y offsets from the object, margins from the pads' "initial"
// y, and the tcp-object distance in xz. v3 stores the initial pads as views
// of the simulator's live body positions, so those margins in fact use the
// current pads; we compute what v3 computes.
double PickPlaceCaging(const SawyerState& s, double gripper_action) {
  constexpr double kPadMargin = 0.05, kXzMargin = 0.005, kObjRadius = 0.015;
  const double left = s.left_pad[1] - s.obj[1];
  const double right = s.obj[1] - s.right_pad[1];
  const double left_margin = std::abs(std::abs(s.obj[1] - s.left_pad[1]) - kPadMargin);
  const double right_margin = std::abs(std::abs(s.obj[1] - s.right_pad[1]) - kPadMargin);
  const double y_caging =
      HamacherProduct(LongTailTolerance(left, kObjRadius, kPadMargin, left_margin),
                      LongTailTolerance(right, kObjRadius, kPadMargin, right_margin));
  const double tcp_obj_xz = std::hypot(s.tcp[0] - s.obj[0], s.tcp[2] - s.obj[2]);
  const double xz_margin =
      std::hypot(s.obj_init[0] - s.tcp_init[0], s.obj_init[2] - s.tcp_init[2]) - kXzMargin;
  const double xz_caging = LongTailTolerance(tcp_obj_xz, 0.0, kXzMargin, xz_margin);
  const double closed = std::clamp(gripper_action, 0.0, 1.0);
  const double caging = HamacherProduct(y_caging, xz_caging);
  const double gripping = caging > 0.97 ? closed : 0.0;
  return (HamacherProduct(caging, gripping) + caging) / 2.0;
}

}  // namespace

RewardTerms PickPlace::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double in_place =
      LongTailTolerance(obj_to_target, 0.0, 0.05, Distance(s.obj_init, s.goal));
  const double grasped = PickPlaceCaging(s, action[3]);

  RewardTerms terms;
  terms.reward = HamacherProduct(grasped, in_place);
  if (tcp_to_obj < 0.02 && s.gripper_opening > 0 && s.obj[2] - 0.01 > s.obj_init[2]) {
    terms.reward += 1.0 + 5.0 * in_place;
  }
  if (obj_to_target < 0.05) terms.reward = 10.0;
  terms.success = obj_to_target <= 0.07;
  terms.near_object = tcp_to_obj <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success =
      s.touching_obj && s.gripper_opening > 0 && s.obj[2] - 0.02 > s.obj_init[2] ? 1.0 : 0.0;
  terms.grasp_reward = grasped;
  terms.in_place_reward = in_place;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void PickPlaceScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const SawyerObs o(env_obs);
  GraspAndCarry(o, o.goal, action);
}

}  // namespace manyworlds::manipulation
