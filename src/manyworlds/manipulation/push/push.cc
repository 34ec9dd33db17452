#include "manyworlds/manipulation/push/push.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kTargetRadius = 0.05;

}  // namespace

SawyerTaskConfig Push::Config() {
  SawyerTaskConfig config =
      TaskConfig("push", "Sawyer arm: push a puck to a goal on the table", "push.xml",
                 {{-0.1, 0.6, 0.02}, {0.1, 0.7, 0.02}}, {{-0.1, 0.8, 0.01}, {0.1, 0.9, 0.02}});
  config.goal_z_at_object = true;
  return config;
}

Push::Push(SawyerOptions options) : SawyerTask(Config(), options) {}

RewardTerms Push::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double in_place = TowardGoal(s, obj_to_target, kTargetRadius);
  const double grasped = CageObject(s, s.obj, action[3], {.high_density = true});

  double reward = 2.0 * grasped;
  if (tcp_to_obj < 0.02 && s.gripper_opening > 0) reward = 2.0 * reward + 1.0 + 5.0 * in_place;
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target < kTargetRadius,
                               .obj_to_target = obj_to_target, .success_radius = kTargetRadius,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = in_place});
}

void Push::InitTaskState(SawyerState& s) const { v1::InitPush(s); }

RewardTerms Push::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return v1::PushStep(s, kTargetRadius);
}

void PushScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                             std::span<float> action) {
  const SawyerObs o(env_obs);
  // Carry 5 mm above the goal so the puck does not drag on the table.
  GraspAndCarry(o, {o.goal[0], o.goal[1], o.goal[2] + 0.005}, action);
}

}  // namespace manyworlds::manipulation
