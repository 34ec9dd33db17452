#include "manyworlds/manipulation/pick_place.h"

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

RewardTerms PickPlace::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double in_place =
      LongTailTolerance(obj_to_target, 0.0, 0.05, Distance(s.obj_init, s.goal));
  CagingParams caging;
  caging.obj_radius = 0.015;
  caging.pad_success_thresh = 0.05;
  caging.xz_thresh = 0.005;
  caging.high_density = true;
  const double grasped = GripperCagingReward(
      {s.left_pad, s.right_pad, s.tcp, s.obj, s.obj_init, s.tcp_init, action[3]}, caging);

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
