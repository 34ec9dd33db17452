#include "manyworlds/manipulation/container/bin_picking.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kTargetRadius = 0.05;
constexpr double kV1Lift = 0.1;  // v3's liftThresh

}  // namespace

SawyerTaskConfig BinPicking::Config() {
  SawyerTaskConfig config =
      TaskConfig("bin-picking", "Sawyer arm: pick a cube out of one bin and put it in the other",
                 "bin_picking.xml", {{-0.21, 0.65, 0.03}, {-0.03, 0.75, 0.03}},
                 {{0.12, 0.7, 0.0}, {0.12, 0.7, 0.0}});
  config.hand_low = {-0.5, 0.40, 0.07};
  config.min_obj_goal_xy = 0.0;  // v3 draws no separation (the bins are apart)
  // v3's goal_space: the goal widened by 0.1 mm in x, 1 mm in y and z.
  config.goal_space = Range3{{0.1199, 0.699, -0.001}, {0.1201, 0.701, 0.001}};
  config.obj_quat = QuatLayout::kWxyz;
  return config;
}

BinPicking::BinPicking(SawyerOptions options) : SawyerTask(Config(), options) {}

void BinPicking::InitTaskState(SawyerState& s) const {
  s.obj_to_target_init = Distance(s.obj, s.goal);
  // v1: v3 lifts from the cube's height at reset; its normaliser is planar
  s.v1_obj_height = s.obj[2];
  s.v1_height_target = s.obj[2] + kV1Lift;
  s.v1_max_dist =
      std::hypot(s.obj_init[0] - s.goal[0], s.obj_init[1] - s.goal[1]) + s.v1_height_target;
}

RewardTerms BinPicking::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double in_place =
      LongTailTolerance(obj_to_target, 0.0, kTargetRadius, s.obj_to_target_init);
  const auto funnel = [&s](const Vec3& centre) {
    return FunnelFloor(std::hypot(s.hand[0] - centre[0], s.hand[1] - centre[1]), 0.03, 0.02, 0.2);
  };
  const double floor = std::min(funnel(s.obj_init), funnel(s.goal));
  const double above_floor = AboveFloor(s.hand[2], floor, 0.05);
  const CagingParams caging{.xz_thresh = 0.01, .desired_gripper_effort = 0.7, .high_density = true};
  const double grasped = CageObject(s, s.obj, action[3], caging);

  const bool near = Distance(s.obj, s.hand) < 0.04;
  const bool held = near && s.gripper_opening >= 0.43 && s.obj[2] - 0.02 > s.obj_init[2];
  RewardTerms terms;
  terms.reward = HamacherProduct(grasped, in_place);
  if (held) terms.reward += 1.0 + 5.0 * HamacherProduct(above_floor, in_place);
  if (obj_to_target < kTargetRadius) terms.reward = 10.0;
  terms.success = obj_to_target <= kTargetRadius;
  terms.near_object = near ? 1.0 : 0.0;
  terms.grasp_success = held ? 1.0 : 0.0;
  terms.grasp_reward = grasped;
  terms.in_place_reward = in_place;
  terms.obj_to_target = obj_to_target;
  return terms;
}

RewardTerms BinPicking::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  const double grip = action[3];
  const double reach_dist = Distance(s.obj, s.tcp);
  // v3 measures the placing distance in the plane, to bin B's origin
  const double place_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  const double reach = v1::Reach(s, s.obj, grip, 0.06, 1.0, 0.05);
  const bool picked = s.obj[2] >= s.v1_height_target - 0.01;
  const bool dropped = v1::Dropped(s, s.obj[2], place_dist, reach_dist);
  const bool over_goal =
      std::abs(s.obj[0] - s.goal[0]) < 0.05 && std::abs(s.obj[1] - s.goal[1]) < 0.05;
  const bool placed = over_goal && s.obj[2] < s.v1_obj_height + 0.05;
  const double pick = v1::LiftBonus(s, s.obj[2], placed || (picked && !dropped), reach_dist < 0.1);
  const double progress = std::max(v1::Progress(s.v1_max_dist, place_dist), 0.0);
  // v3: over bin B, opening the gripper pays (-200 a[3]); once placed, that
  // and the progress bonus are the whole reward
  const double release = -200.0 * grip;
  double reward = 0;
  if (placed) {
    reward = release + progress;
  } else {
    double place = 0;
    if (picked && reach_dist < 0.1 && !dropped) place = over_goal ? release + progress : progress;
    reward = reach + pick + place;
  }
  RewardTerms terms;
  terms.reward = reward;
  // v3's evaluate_state on v1's (reward, False, False, planar distance, 0, 0)
  terms.success = place_dist <= kTargetRadius;
  terms.obj_to_target = place_dist;
  return terms;
}

void BinPickingScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  SawyerObs o(env_obs);
  // Bin A's y walls are 4 cm from the cube's centre at the range's ends; the
  // open fingers reach 5.5 cm. Grip at most 2.5 cm from the bin's centre
  // line in y: the closing fingers drag the cube there.
  o.obj1[1] = std::clamp(o.obj1[1], 0.675, 0.725);
  // The cube's bottom 3 cm over the walls (centre 0.11), then down to bin
  // B's floor.
  GraspAndCarryOver(o, {o.goal[0], o.goal[1], 0.03}, 0.11, 0.01, action);
}

}  // namespace manyworlds::manipulation
