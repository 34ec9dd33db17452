#include "manyworlds/manipulation/hole/pick_out_of_hole.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {

SawyerTaskConfig PickOutOfHole::Config() {
  SawyerTaskConfig config =
      TaskConfig("pick-out-of-hole", "Sawyer arm: pick a puck out of a hole in the table",
                 "pick_out_of_hole.xml", {{0.0, 0.75, 0.02}, {0.0, 0.75, 0.02}},
                 {{-0.1, 0.5, 0.15}, {0.1, 0.6, 0.3}});
  config.hand_low = {-0.5, 0.40, -0.05};
  config.obj_quat = QuatLayout::kWxyz;
  return config;
}

PickOutOfHole::PickOutOfHole(SawyerOptions options) : SawyerTask(Config(), options) {}

RewardTerms PickOutOfHole::ComputeReward(const SawyerState& s,
                                         std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  const double radius = std::hypot(s.tcp[0] - s.obj_init[0], s.tcp[1] - s.obj_init[1]);
  const double above_floor = AboveFloor(s.tcp[2], FunnelFloor(radius, 0.03, 0.015, 0.15), 0.02);
  const CagingParams caging{.pad_success_thresh = 0.02,
                            .xz_thresh = 0.03,
                            .desired_gripper_effort = 0.1,
                            .high_density = true};
  const double grasped = CageObject(s, s.obj, action[3], caging);
  const double in_place = TowardGoal(s, obj_to_target, 0.02);

  const bool held = tcp_to_obj < 0.04 && s.gripper_opening >= 0.33 &&
                    s.obj[2] - 0.02 > s.obj_init[2];
  double reward = HamacherProduct(grasped, in_place);
  if (held) reward += 1.0 + 5.0 * HamacherProduct(in_place, above_floor);
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target < 0.05,
                               .obj_to_target = obj_to_target, .success_radius = 0.07,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = in_place,
                               .grasp_success = held ? 1.0 : 0.0});
}

void PickOutOfHole::InitTaskState(SawyerState& s) const {
  v1::InitPickPlace(s, s.obj_init[2], 0.11);  // v3's liftThresh
}

RewardTerms PickOutOfHole::ComputeRewardV1(const SawyerState& s,
                                           std::span<const float> action) const {
  return v1::PickPlaceStep(s, action[3], 0.07, /*lift_from_start=*/true);
}

void PickOutOfHoleScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                      std::span<float> action) {
  const SawyerObs o(env_obs);
  // Straight up to 5 cm above the top (or the goal's height), then across.
  GraspAndCarryOver(o, o.goal, std::max(0.13, o.goal[2]), 0.02, action);
}

}  // namespace manyworlds::manipulation
