#include "manyworlds/manipulation/pick_place/basketball.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

// Meta-World v3: the goal is the ring's centre, 8.3 cm in front of the
// stand's position and 25 cm up; success holds the ball above it, at
// height 0.3 (5 cm over the ring plane), z counting twice.
constexpr Vec3 kGoalOnStand{0.0, -0.083, 0.25};
constexpr double kTargetHeight = 0.3;
constexpr double kTargetRadius = 0.08;
// The ball's centre from the ring's axis that clears the ring on the way
// up: ring radius 0.085 + tube 0.006 + ball 0.03 + 1.9 cm.
constexpr double kRingClearance = 0.14;
constexpr Vec3 kZTwice{1.0, 1.0, 2.0};

}  // namespace

SawyerTaskConfig Basketball::Config() {
  // v3 draws the stand in (-0.1, 0.85, 0)-(0.1, 0.9, 0); its 0.15 m
  // ball-stand rule can never bind (the ranges are 0.15 apart in y), so
  // there is none here.
  SawyerTaskConfig config = TaskConfig("basketball", "Sawyer arm: put a ball through a hoop",
                                       "basketball.xml", {{-0.1, 0.6, 0.03}, {0.1, 0.7, 0.03}},
                                       {{-0.1, 0.85 + kGoalOnStand[1], kGoalOnStand[2]},
                                        {0.1, 0.9 + kGoalOnStand[1], kGoalOnStand[2]}});
  config.min_obj_goal_xy = 0.0;
  // v3's goal_space widens the goal's height by 0.1 mm either way.
  config.goal_space = Range3{{-0.1, 0.85 + kGoalOnStand[1], kGoalOnStand[2] - 1e-4},
                             {0.1, 0.9 + kGoalOnStand[1], kGoalOnStand[2] + 1e-4}};
  // obs[7:11]: the ball's (w, x, y, z), as v3 writes its body's xquat.
  config.obj_quat = QuatLayout::kWxyz;
  return config;
}

Basketball::Basketball(SawyerOptions options)
    : GoalFixtureTask(Config(), "hoop", kGoalOnStand, options) {}

RewardTerms Basketball::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const Vec3 target{s.goal[0], s.goal[1], kTargetHeight};
  const double obj_to_target = WeightedDistance(s.obj, target, kZTwice);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double in_place = LongTailTolerance(obj_to_target, 0.0, kTargetRadius,
                                            WeightedDistance(s.obj_init, target, kZTwice));
  const CagingParams caging{.obj_radius = 0.025, .pad_success_thresh = 0.06, .high_density = true};
  const bool held = HeldAndLifted(s, 0.035, 0.01);
  // A lifted ball counts as grasped whatever the pads look like.
  const double grasped = held ? 1.0 : CageObject(s, s.obj, action[3], caging);

  double reward = HamacherProduct(grasped, in_place);
  if (held) reward += 1.0 + 5.0 * in_place;
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target < kTargetRadius,
                               .obj_to_target = obj_to_target, .success_radius = kTargetRadius,
                               .tcp_to_obj = tcp_to_obj, .near_radius = 0.05, .grasped = grasped,
                               .in_place = in_place,
                               .grasp_success = OpenAndLifted(s) ? 1.0 : 0.0});
}

void Basketball::InitTaskState(SawyerState& s) const {
  v1::InitPickPlace(s, s.obj_init[2], 0.3);  // v3's liftThresh
}

RewardTerms Basketball::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  return v1::PickPlaceStep(s, action[3], kTargetRadius);
}

void BasketballScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3& ball = o.obj1;
  const Vec3 above{o.goal[0], o.goal[1], kTargetHeight};
  const double xy_error = std::hypot(ball[0] - above[0], ball[1] - above[1]);
  // Up first, then across above the ring to the point over its centre. A
  // ball that starts within kRingClearance of the ring's axis would meet the
  // ring from below on the way up (and be torn from the grip): it is first
  // carried away from the axis at its own height.
  Vec3 carry_to = above;
  if (xy_error > 0.02 && ball[2] < kTargetHeight - 0.02) {
    carry_to = {ball[0], ball[1], kTargetHeight + 0.01};
    if (xy_error < kRingClearance) {
      const double out = (kRingClearance + 0.02) / std::max(xy_error, 1e-6);
      carry_to = {above[0] + (ball[0] - above[0]) * out, above[1] + (ball[1] - above[1]) * out,
                  std::max(ball[2], 0.06)};
    }
  }
  GraspParams params;
  // Closed on the 6 cm ball the opening is about 0.7.
  params.closed_on_object = 0.8;
  GraspAndCarry(o, carry_to, action, params);
}

}  // namespace manyworlds::manipulation
