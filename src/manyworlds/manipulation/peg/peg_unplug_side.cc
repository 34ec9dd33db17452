#include "manyworlds/manipulation/peg/peg_unplug_side.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOnWall{0.194, 0.0, 0.131};
constexpr double kTargetRadius = 0.07;  // success
constexpr double kRewardRadius = 0.05;  // in-place tolerance, and reward 10
// The policy's grasp point: behind the plug's end and above its axis,
// where the palm just clears the block's top.
constexpr Vec3 kGraspFromEnd{-0.02, 0.0, 0.011};

}  // namespace

SawyerTaskConfig PegUnplugSide::Config() {
  SawyerTaskConfig config =
      TaskConfig("peg-unplug-side", "Sawyer arm: pull a plug sideways out of its socket",
                 "peg_unplug_side.xml", {{-0.25, 0.6, -0.001}, {-0.15, 0.8, 0.001}});
  config.hand_init = {0.0, 0.6, 0.2};
  for (int i = 0; i < 3; ++i) {
    config.goal_low[i] = config.obj_low[i] + kGoalOnWall[i];
    config.goal_high[i] = config.obj_high[i] + kGoalOnWall[i];
  }
  config.min_obj_goal_xy = 0.0;
  config.obj_quat = QuatLayout::kWxyz;
  return config;
}

PegUnplugSide::PegUnplugSide(SawyerOptions options) : SawyerTask(Config(), options) {
  const sim::IdLookup ids(model(), config().xml_file);
  box_ = ids.Body("box");
  plug_end_ = ids.Site("obj_point");
}

Vec3 PegUnplugSide::DeriveGoal(const Vec3& obj, const Vec3&) const {
  return {obj[0] + kGoalOnWall[0], obj[1] + kGoalOnWall[1], obj[2] + kGoalOnWall[2]};
}

void PegUnplugSide::PlaceObjects(mjModel* m, mjData*) { PlaceFixture(m, box_, obj_pos()); }

void PegUnplugSide::RefreshTaskState(const mjData* d, SawyerState& state) const {
  state.obj = SitePosition(d, plug_end_);
}

void PegUnplugSide::InitTaskState(SawyerState& state) const {
  state.obj_init = state.obj;
  state.v1_max_dist = Distance(state.goal, state.obj_init);  // v3's maxPlacingDist
}

RewardTerms PegUnplugSide::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  const double obj_to_target = Distance(s.obj, s.goal);
  const CagingParams caging{
      .obj_radius = 0.025, .desired_gripper_effort = 0.8, .high_density = true};
  const double grasped = CageObject(s, s.obj, action[3], caging);
  const double in_place = TowardGoal(s, obj_to_target, kRewardRadius);
  const bool pulling = s.gripper_opening > 0.5 && s.obj[0] - s.obj_init[0] > 0.015;

  double reward = 2.0 * grasped;
  if (pulling && tcp_to_obj < 0.035) reward = 1.0 + 2.0 * grasped + 5.0 * in_place;
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target <= kRewardRadius,
                               .obj_to_target = obj_to_target, .success_radius = kTargetRadius,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = in_place,
                               .grasp_success = pulling ? 1.0 : 0.0});
}

RewardTerms PegUnplugSide::ComputeRewardV1(const SawyerState& s,
                                           std::span<const float> action) const {
  const double reach_dist = Distance(s.obj, s.tcp);
  const double reach_xy = std::hypot(s.obj[0] - s.tcp[0], s.obj[1] - s.tcp[1]);
  // v3 measures the height change from the configured hand start here, not the tcp's
  double reach = reach_xy < 0.05 ? -reach_dist : -reach_xy - 2.0 * std::abs(s.tcp[2] - s.hand_init[2]);
  if (reach_dist < 0.05) reach = -reach_dist + std::max(static_cast<double>(action[3]), 0.0) / 50.0;
  const double place_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  const double place =
      reach_dist < 0.05 ? std::max(v1::Progress(s.v1_max_dist, place_dist), 0.0) : 0.0;
  return v1::StepTerms(reach + place, place_dist, kTargetRadius);
}

void PegUnplugSideScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                      std::span<float> action) {
  SawyerObs o(env_obs);
  // Grasp and carry the grasp point instead of the plug's end.
  for (int i = 0; i < 3; ++i) o.obj1[i] += kGraspFromEnd[i];
  GraspParams grasp;
  grasp.closed_on_object = 0.93;  // the block holds the pads at 0.86
  grasp.held_distance = 0.02;
  grasp.over_object_xy = 0.006;
  const Vec3 carry_to{o.goal[0] + kGraspFromEnd[0] + 0.01, o.obj1[1], o.obj1[2]};
  GraspAndCarry(o, carry_to, action, grasp);
}

}  // namespace manyworlds::manipulation
