#include "manyworlds/manipulation/basketball.h"

#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

// The goal relative to the stand's foot.
constexpr Vec3 kGoalOnStand{0.0, -0.1, 0.2};
constexpr double kSuccessRadius = 0.08;
// The ball's bottom clears the ring (5 cm above the goal) with this centre
// height above the goal.
constexpr double kOverRing = 0.11;

}  // namespace

SawyerTaskConfig Basketball::Config() {
  SawyerTaskConfig config;
  config.id = "basketball";
  config.description = "Sawyer arm: put a ball through a hoop";
  config.xml_file = "basketball.xml";
  config.obj_low = {-0.1, 0.6, 0.03};
  config.obj_high = {0.1, 0.7, 0.03};
  config.goal_low = {-0.1, 0.85 + kGoalOnStand[1], kGoalOnStand[2]};
  config.goal_high = {0.1, 0.9 + kGoalOnStand[1], kGoalOnStand[2]};
  return config;
}

Basketball::Basketball(SawyerOptions options) : SawyerTask(Config(), options) {
  hoop_ = sim::IdLookup(model(), config().xml_file).Body("hoop");
}

void Basketball::PlaceObjects(mjModel* m, mjData* d) {
  SawyerTask::PlaceObjects(m, d);
  const Vec3& goal = goal_pos();
  PlaceFixture(m, hoop_,
               {goal[0] - kGoalOnStand[0], goal[1] - kGoalOnStand[1], goal[2] - kGoalOnStand[2]});
}

RewardTerms Basketball::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const Vec3 weights{1.0, 1.0, 2.0};
  const double in_place =
      LongTailTolerance(WeightedDistance(s.obj, s.goal, weights), 0.0, kSuccessRadius,
                        WeightedDistance(s.obj_init, s.goal, weights));
  CagingParams caging;
  caging.obj_radius = 0.025;
  caging.pad_success_thresh = 0.06;
  caging.xz_thresh = 0.005;
  caging.high_density = true;
  const bool held = HeldAndLifted(s, 0.035, 0.01);
  // A lifted ball counts as grasped whatever the pads look like.
  const double grasped = held ? 1.0 : CageObject(s, s.obj, action[3], caging);

  RewardTerms terms;
  terms.reward = HamacherProduct(grasped, in_place);
  if (held) terms.reward += 1.0 + 5.0 * in_place;
  terms.success = obj_to_target <= kSuccessRadius;
  if (terms.success) terms.reward = 10.0;
  terms.near_object = tcp_to_obj <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = GraspSuccess(s);
  terms.grasp_reward = grasped;
  terms.in_place_reward = in_place;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void BasketballScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3& ball = o.obj1;
  const Vec3& goal = o.goal;
  const double high = goal[2] + kOverRing;
  const double xy_error = std::hypot(ball[0] - goal[0], ball[1] - goal[1]);
  Vec3 carry_to;
  if (xy_error > 0.02 && ball[2] < high - 0.02) {
    carry_to = {ball[0], ball[1], high};  // straight up: the ring may be in the way
  } else if (xy_error > 0.01) {
    carry_to = {goal[0], goal[1], high};
  } else {
    carry_to = goal;  // down through the ring
  }
  GraspParams params;
  // Closed on the 6 cm ball the opening is about 0.7.
  params.closed_on_object = 0.8;
  GraspAndCarry(o, carry_to, action, params);
}

}  // namespace manyworlds::manipulation
