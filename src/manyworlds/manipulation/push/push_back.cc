#include "manyworlds/manipulation/push/push_back.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {

SawyerTaskConfig PushBack::Config() {
  SawyerTaskConfig config =
      TaskConfig("push-back", "Sawyer arm: bring a block back toward the robot", "push_back.xml",
                 {{-0.1, 0.8, 0.02}, {0.1, 0.85, 0.02}}, {{-0.1, 0.6, 0.02}, {0.1, 0.7, 0.02}});
  config.goal_z_at_object = true;
  // v3's goal_space: the goals' box with z widened 0.1 mm either way.
  config.goal_space = Range3{{-0.1, 0.6, 0.0199}, {0.1, 0.7, 0.0201}};
  return config;
}

PushBack::PushBack(SawyerOptions options) : SawyerTask(Config(), options) {}

RewardTerms PushBack::ComputeReward(const SawyerState& s, std::span<const float>) const {
  constexpr double kTargetRadius = 0.05;
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double obj_to_target = Distance(s.obj, s.goal);
  const double obj_to_target_init = Distance(s.obj_init, s.goal);
  const double in_place = LongTailTolerance(obj_to_target, 0.0, kTargetRadius, obj_to_target_init);
  const double grasped = SweepCaging(s, 0.007, 0.003, 0.01);

  double reward = HamacherProduct(grasped, in_place);
  if (tcp_to_obj < 0.01 && s.gripper_opening > 0 && s.gripper_opening < 0.55 &&
      obj_to_target_init - obj_to_target > 0.01) {
    reward += 1.0 + 5.0 * in_place;
  }
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target < kTargetRadius,
                               .obj_to_target = obj_to_target, .success_radius = 0.07,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = in_place});
}

void PushBack::InitTaskState(SawyerState& s) const { v1::InitPush(s); }

RewardTerms PushBack::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return v1::PushStep(s, 0.07);
}

void PushBackScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                 std::span<float> action) {
  const SawyerObs o(env_obs);
  GraspAndCarry(o, {o.goal[0], o.goal[1], o.goal[2] + 0.005}, action);
}

}  // namespace manyworlds::manipulation
