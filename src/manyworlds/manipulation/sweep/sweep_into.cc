#include "manyworlds/manipulation/sweep/sweep_into.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kTargetRadius = 0.05;

}  // namespace

SawyerTaskConfig SweepInto::Config() {
  SawyerTaskConfig config;
  config.id = "sweep-into";
  config.description = "Sawyer arm: sweep a puck into the goal pocket";
  config.xml_file = "sweep_into.xml";
  config.obj_low = {-0.1, 0.6, 0.02};
  config.obj_high = {0.1, 0.7, 0.02};
  // The pocket does not move: the goal is one point.
  config.goal_low = {0.0, 0.84, 0.02};
  config.goal_high = {0.0, 0.84, 0.02};
  return config;
}

SweepInto::SweepInto(SawyerOptions options) : SawyerTask(Config(), options) {}

RewardTerms SweepInto::ComputeReward(const SawyerState& s, std::span<const float> /*action*/) const {
  // Meta-World v3 measures in the table plane: the target at the puck's height.
  const Vec3 target{s.goal[0], s.goal[1], s.obj[2]};
  const double obj_to_target = Distance(s.obj, target);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double in_place =
      LongTailTolerance(obj_to_target, 0.0, kTargetRadius, Distance(s.obj_init, target));
  // v3's sweep-into caging: a 5 mm grip band, 1 cm in xz, no gripper-action term.
  const double grasped = SweepCaging(s, 0.02, 0.005, 0.01);

  RewardTerms terms;
  terms.reward = 2.0 * grasped + 6.0 * HamacherProduct(grasped, in_place);
  if (obj_to_target < kTargetRadius) terms.reward = 10.0;
  terms.success = obj_to_target <= kTargetRadius;
  terms.near_object = tcp_to_obj <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = s.touching_obj && s.gripper_opening > 0 ? 1.0 : 0.0;
  terms.grasp_reward = grasped;
  terms.in_place_reward = in_place;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void SweepInto::InitTaskState(SawyerState& s) const {
  s.v1_max_dist = std::hypot(s.obj_init[0] - s.goal[0], s.obj_init[1] - s.goal[1]);
}

RewardTerms SweepInto::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double reach_dist = Distance(s.obj, s.tcp);
  double push_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  double reward = -reach_dist;
  // v3: a puck 5 cm below its start, over the table's span in y, counts as in
  if (s.obj[2] < s.obj_init[2] - 0.05 && s.obj[1] > 0.4 && s.obj[1] < 1.0) {
    reward = 0.0;
    push_dist = 0.0;
  }
  if (reach_dist < 0.05) reward += std::max(v1::Progress(s.v1_max_dist, push_dist), 0.0);
  RewardTerms terms;
  terms.reward = reward;
  terms.success = push_dist <= kTargetRadius;
  terms.near_object = 1.0;
  terms.obj_to_target = push_dist;
  return terms;
}

void SweepIntoScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const SawyerObs o(env_obs);
  // The goal is at the puck's centre height; 5 mm higher the puck does not
  // drag on the table.
  GraspAndCarry(o, {o.goal[0], o.goal[1], o.goal[2] + 0.005}, action);
}

}  // namespace manyworlds::manipulation
