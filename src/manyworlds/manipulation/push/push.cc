#include "manyworlds/manipulation/push/push.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kTargetRadius = 0.05;

}  // namespace

SawyerTaskConfig Push::Config() {
  SawyerTaskConfig config;
  config.id = "push";
  config.description = "Sawyer arm: push a puck to a goal on the table";
  config.xml_file = "push.xml";
  config.obj_low = {-0.1, 0.6, 0.02};
  config.obj_high = {0.1, 0.7, 0.02};
  config.goal_low = {-0.1, 0.8, 0.01};
  config.goal_high = {0.1, 0.9, 0.02};
  config.goal_z_at_object = true;
  return config;
}

Push::Push(SawyerOptions options) : SawyerTask(Config(), options) {}

RewardTerms Push::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double in_place =
      LongTailTolerance(obj_to_target, 0.0, kTargetRadius, Distance(s.obj_init, s.goal));
  CagingParams caging;
  caging.obj_radius = 0.015;
  caging.pad_success_thresh = 0.05;
  caging.object_reach_radius = 0.01;
  caging.xz_thresh = 0.005;
  caging.high_density = true;
  const double grasped = GripperCagingReward(
      {s.left_pad, s.right_pad, s.tcp, s.obj, s.obj_init, s.tcp_init, action[3]}, caging);

  RewardTerms terms;
  terms.reward = 2.0 * grasped;
  if (tcp_to_obj < 0.02 && s.gripper_opening > 0) {
    terms.reward = 2.0 * terms.reward + 1.0 + 5.0 * in_place;
  }
  if (obj_to_target < kTargetRadius) terms.reward = 10.0;
  terms.success = obj_to_target <= kTargetRadius;
  terms.near_object = tcp_to_obj <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success =
      s.touching_obj && s.gripper_opening > 0 && s.obj[2] - 0.02 > s.obj_init[2] ? 1.0 : 0.0;
  terms.grasp_reward = grasped;
  terms.in_place_reward = in_place;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void Push::InitTaskState(SawyerState& s) const {
  s.v1_max_dist = std::hypot(s.obj_init[0] - s.goal[0], s.obj_init[1] - s.goal[1]);
}

RewardTerms Push::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double reach_dist = Distance(s.tcp, s.obj);
  const double push_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  RewardTerms terms;
  terms.reward = v1::ReachThenProgress(reach_dist, s.v1_max_dist, push_dist);
  // v3's evaluate_state on v1's (reward, 0, 0, push_dist, 0, 0)
  terms.success = push_dist <= kTargetRadius;
  terms.near_object = 1.0;
  terms.grasp_success = 0.0;
  terms.obj_to_target = push_dist;
  return terms;
}

void PushScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                             std::span<float> action) {
  const SawyerObs o(env_obs);
  // Carry 5 mm above the goal so the puck does not drag on the table.
  GraspAndCarry(o, {o.goal[0], o.goal[1], o.goal[2] + 0.005}, action);
}

}  // namespace manyworlds::manipulation
