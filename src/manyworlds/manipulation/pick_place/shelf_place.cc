#include "manyworlds/manipulation/pick_place/shelf_place.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kGoalHeight = 0.3;  // goal above the bookcase's foot
constexpr double kHalfBlock = 0.02;
constexpr double kShelfDepth = 0.08;   // shelf front edge in front of the goal
constexpr double kBlockedZone = 0.15;  // half-width in x of the zone below the shelf
constexpr double kShelfTop = 0.24;     // v3's height of the zone under the shelf
constexpr double kSuccessRadius = 0.07;
constexpr double kRewardRadius = 0.05;

}  // namespace

SawyerTaskConfig ShelfPlace::Config() {
  SawyerTaskConfig config =
      TaskConfig("shelf-place", "Sawyer arm: pick up a block and put it on a shelf",
                 "shelf_place.xml", {{-0.1, 0.5, kHalfBlock}, {0.1, 0.6, kHalfBlock}},
                 {{-0.1, 0.8, kGoalHeight}, {0.1, 0.9, kGoalHeight}});
  // v3's goal_space: z widened 1 mm either way (v3 draws the shelf's height
  // in (-0.001, 0.001); ours stands on the table).
  config.goal_space = Range3{{-0.1, 0.8, 0.299}, {0.1, 0.9, 0.301}};
  return config;
}

ShelfPlace::ShelfPlace(SawyerOptions options)
    : GoalFixtureTask(Config(), "shelf", {0.0, 0.0, kGoalHeight}, options) {}

RewardTerms ShelfPlace::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  // Meta-World v3's shelf-place reward.
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  double in_place = TowardGoal(s, obj_to_target, kRewardRadius);
  // the shared caging term, not high-density
  const CagingParams caging{.obj_radius = 0.02, .xz_thresh = 0.01};
  const double grasped = CageObject(s, s.obj, action[3], caging);

  double reward = HamacherProduct(grasped, in_place);
  // Below the shelf top (z 0.24) in front of the goal the shelf is in the
  // way: there, and under the shelf past the goal, nearness is not progress.
  // These change only the carrying bonus below, as in v3.
  const bool below_shelf = s.obj[2] > 0.0 && s.obj[2] < kShelfTop &&
                           s.obj[0] > s.goal[0] - kBlockedZone && s.obj[0] < s.goal[0] + kBlockedZone;
  const double zone_start = s.goal[1] - 3.0 * kRewardRadius;
  if (below_shelf && s.obj[1] > zone_start && s.obj[1] < s.goal[1]) {
    const double depth = (kShelfTop - s.obj[2]) / kShelfTop;
    const double under = (s.obj[1] - zone_start) / (3.0 * kRewardRadius);
    in_place = std::clamp(in_place - HamacherProduct(under, depth), 0.0, 1.0);
  }
  if (below_shelf && s.obj[1] > s.goal[1]) in_place = 0.0;
  if (HeldAndLifted(s, 0.025, 0.01)) reward += 1.0 + 5.0 * in_place;
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target < kRewardRadius,
                               .obj_to_target = obj_to_target, .success_radius = kSuccessRadius,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = in_place});
}

void ShelfPlace::InitTaskState(SawyerState& s) const {
  v1::InitPickPlace(s, s.obj_init[2], 0.04);  // v3's liftThresh
}

RewardTerms ShelfPlace::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  return v1::PickPlaceStep(s, action[3], 0.07);
}

void ShelfPlaceScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3& block = o.obj1;
  const Vec3& goal = o.goal;
  const double shelf_front = goal[1] - kShelfDepth;
  Vec3 carry_to;
  if (block[1] < shelf_front - 0.03 && block[2] < goal[2] + 0.008) {
    // Rise in front of the bookcase until the block's bottom clears the
    // shelf; 9 cm back, the front of the palm (6 cm ahead of the tcp)
    // passes the shelf's edge.
    carry_to = {goal[0], shelf_front - 0.09, goal[2] + 0.025};
  } else {
    carry_to = {goal[0], goal[1], goal[2] + 0.015};
  }
  GraspAndCarry(o, carry_to, action);
}

}  // namespace manyworlds::manipulation
