#include "manyworlds/manipulation/push/soccer.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/manipulation/push_from_behind.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kTargetRadius = 0.07;
constexpr double kBallRadius = 0.026;
constexpr Vec3 kXThrice{3.0, 1.0, 1.0};

}  // namespace

SawyerTaskConfig Soccer::Config() {
  // v3 draws the ball at z 0.03; ours rests at its radius.
  return TaskConfig("soccer", "Sawyer arm: push a ball into a goal net", "soccer.xml",
                    {{-0.1, 0.6, kBallRadius}, {0.1, 0.7, kBallRadius}},
                    {{-0.1, 0.8, 0.0}, {0.1, 0.9, 0.0}});
}

Soccer::Soccer(SawyerOptions options) : GoalFixtureTask(Config(), "net", {}, options) {}

RewardTerms Soccer::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double target_to_obj = WeightedDistance(s.obj, s.goal, kXThrice);
  double in_place = LongTailTolerance(target_to_obj, 0.0, kTargetRadius,
                                      WeightedDistance(s.obj, s.obj_init, kXThrice));
  const double goal_line = s.goal[1] - 0.1;
  if (s.obj[1] > goal_line && std::abs(s.obj[0] - s.goal[0]) > 0.1) {
    in_place = std::clamp(in_place - 2.0 * (s.obj[1] - goal_line) / (1.0 - goal_line), 0.0, 1.0);
  }
  const double grasped = SweepCaging(s, 0.013, 0.01, 0.005);

  RewardTerms terms;
  terms.reward = 3.0 * grasped + 6.5 * in_place;
  if (target_to_obj < kTargetRadius) terms.reward = 10.0;
  // v3's success reads the unweighted distance (the one its reward returns
  // for info), while the 10 above reads the weighted one.
  terms.obj_to_target = Distance(s.obj, s.goal);
  terms.success = terms.obj_to_target <= kTargetRadius;
  terms.near_object = tcp_to_obj <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = GraspSuccess(s);
  terms.grasp_reward = grasped;
  terms.in_place_reward = in_place;
  return terms;
}

void Soccer::InitTaskState(SawyerState& s) const { v1::InitPush(s); }

RewardTerms Soccer::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return v1::PushStep(s, 0.07);
}

void SoccerScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                               std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3& ball = o.obj1;
  // Bring the ball onto the goal's axis 10 cm in front of the net first,
  // then straight in (the reward's 10 counts x three times).
  const bool before_mouth = ball[1] < o.goal[1] - 0.1;
  const Vec3 target = before_mouth ? Vec3{o.goal[0], o.goal[1] - 0.1, kBallRadius}
                                   : Vec3{o.goal[0], o.goal[1], kBallRadius};
  PushParams params;
  params.low = 0.015;     // the fingers' tips at the table, under the ball's centre
  params.behind = 0.045;  // the ball's radius and the fingers' half-width
  PushFromBehind(o, ball, target, params, action);
}

}  // namespace manyworlds::manipulation
