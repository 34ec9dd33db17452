#include "manyworlds/manipulation/pick_place/pick_place.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {

SawyerTaskConfig PickPlace::Config() {
  return TaskConfig("pick-place", "Sawyer arm: pick up a puck and place it at a goal in space",
                    "pick_place.xml", {{-0.1, 0.6, 0.02}, {0.1, 0.7, 0.02}},
                    {{-0.1, 0.8, 0.05}, {0.1, 0.9, 0.3}});
}

PickPlace::PickPlace(SawyerOptions options) : SawyerTask(Config(), options) {}

namespace {

// Meta-World v3's pick-place caging: pads and tcp caged as in
// object_tasks.h, the gripper action counted once caging exceeds 0.97.
double PickPlaceCaging(const SawyerState& s, double gripper_action) {
  const double caging = HamacherProduct(PadCagingY(s, 0.015, 0.05), TcpCagingXz(s, 0.005));
  const double gripping = caging > 0.97 ? std::clamp(gripper_action, 0.0, 1.0) : 0.0;
  return (HamacherProduct(caging, gripping) + caging) / 2.0;
}

}  // namespace

RewardTerms PickPlace::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double in_place = TowardGoal(s, obj_to_target, 0.05);
  const double grasped = PickPlaceCaging(s, action[3]);

  double reward = HamacherProduct(grasped, in_place);
  if (tcp_to_obj < 0.02 && s.gripper_opening > 0 && s.obj[2] - 0.01 > s.obj_init[2]) {
    reward += 1.0 + 5.0 * in_place;
  }
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target < 0.05,
                               .obj_to_target = obj_to_target, .success_radius = 0.07,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = in_place});
}

void PickPlace::InitTaskState(SawyerState& s) const {
  v1::InitPickPlace(s, s.obj_init[2], 0.04);
}

RewardTerms PickPlace::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  return v1::PickPlaceStep(s, action[3], 0.07);
}

void PickPlaceScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const SawyerObs o(env_obs);
  GraspAndCarry(o, o.goal, action);
}

}  // namespace manyworlds::manipulation
