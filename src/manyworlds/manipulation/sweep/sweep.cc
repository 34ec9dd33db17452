#include "manyworlds/manipulation/sweep/sweep.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kTargetRadius = 0.05;
constexpr double kPuckCentreHeight = 0.02;
constexpr double kPuckRadius = 0.02;

}  // namespace

SawyerTaskConfig Sweep::Config(SweepVariant variant) {
  const bool into = variant == SweepVariant::kInto;
  SawyerTaskConfig config;
  config.id = into ? "sweep-into" : "sweep";
  config.description = into ? "Sawyer arm: sweep a puck into the goal pocket"
                            : "Sawyer arm: sweep a puck sideways to the edge of the table";
  config.xml_file = into ? "sweep_into.xml" : "sweep.xml";
  config.obj_low = {-0.1, 0.6, kPuckCentreHeight};
  config.obj_high = {0.1, 0.7, kPuckCentreHeight};
  if (into) {
    // The pocket does not move: the goal is one point.
    config.goal_low = {0.0, 0.84, 0.02};
    config.goal_high = {0.0, 0.84, 0.02};
    // v3's goal_space: that point widened by 1 mm in x, 0.1 mm in y and z.
    config.goal_space = Range3{{-0.001, 0.8399, 0.0199}, {0.001, 0.8401, 0.0201}};
  } else {
    // Only bounds the observation: the goal is DeriveGoal's.
    config.goal_low = {0.49, 0.6, 0.0};
    config.goal_high = {0.51, 0.7, 0.02};
    // obs[7:11]: the puck's (w, x, y, z), as v3 writes its body's xquat
    // (sweep-into's v3 writes (x, y, z, w)).
    config.obj_quat = QuatLayout::kWxyz;
  }
  return config;
}

Sweep::Sweep(SweepVariant variant, SawyerOptions options)
    : SawyerTask(Config(variant), options), variant_(variant) {}

Vec3 Sweep::DeriveGoal(const Vec3& obj, const Vec3& drawn_goal) const {
  if (variant_ == SweepVariant::kInto) return SawyerTask::DeriveGoal(obj, drawn_goal);
  // Meta-World v3 does not sample sweep's goal: it is the table's edge on
  // the puck's row (its goal range only bounds the observation).
  return {0.5, obj[1], 0.01};
}

RewardTerms Sweep::ComputeReward(const SawyerState& s, std::span<const float> /*action*/) const {
  const bool into = variant_ == SweepVariant::kInto;
  // sweep-into: Meta-World v3 measures in the table plane, the target at
  // the puck's height.
  const Vec3 target = into ? Vec3{s.goal[0], s.goal[1], s.obj[2]} : s.goal;
  const double obj_to_target = Distance(s.obj, target);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double in_place =
      LongTailTolerance(obj_to_target, 0.0, kTargetRadius, Distance(s.obj_init, target));
  // v3's caging, no gripper-action term: sweep's pads within 1 cm past the
  // puck's radius and 5 mm in xz; sweep-into's a 5 mm grip band, 1 cm in xz.
  const double grasped =
      into ? SweepCaging(s, kPuckRadius, 0.005, 0.01) : SweepCaging(s, kPuckRadius, 0.01, 0.005);

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

void Sweep::InitTaskState(SawyerState& s) const { v1::InitPush(s); }

RewardTerms Sweep::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double reach_dist = Distance(s.obj, s.tcp);
  double push_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  double reward = -reach_dist;
  // v3: once the puck has fallen off the table, reach and distance count as
  // 0 (the bonus still needs the tcp within 5 cm); sweep-into: a puck 5 cm
  // below its start, over the table's span in y, counts as in.
  const bool over_table = variant_ == SweepVariant::kEdge || (s.obj[1] > 0.4 && s.obj[1] < 1.0);
  if (s.obj[2] < s.obj_init[2] - 0.05 && over_table) {
    reward = 0.0;
    push_dist = 0.0;
  }
  if (reach_dist < 0.05) reward += std::max(v1::Progress(s.v1_max_dist, push_dist), 0.0);
  return v1::StepTerms(reward, push_dist, kTargetRadius);
}

void SweepScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                              std::span<float> action) {
  const SawyerObs o(env_obs);
  // 5 mm above the puck's centre height the puck does not drag on the
  // table; sweep-into's goal is at that height, sweep's on the table.
  const double carry_z =
      variant_ == SweepVariant::kInto ? o.goal[2] + 0.005 : kPuckCentreHeight + 0.005;
  GraspAndCarry(o, {o.goal[0], o.goal[1], carry_z}, action);
}

}  // namespace manyworlds::manipulation
