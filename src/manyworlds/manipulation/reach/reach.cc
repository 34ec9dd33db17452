#include "manyworlds/manipulation/reach/reach.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/policy_utils.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/manipulation/wall.h"

namespace manyworlds::manipulation {

SawyerTaskConfig Reach::Config(ReachVariant variant) {
  if (variant == ReachVariant::kWall) {
    return wall::WallConfig("reach-wall", "Sawyer arm: reach a goal behind a wall",
                            "reach_wall.xml", 0.05, 0.3);
  }
  return TaskConfig("reach", "Sawyer arm: move the gripper to a goal position in space",
                    "reach.xml", {{-0.1, 0.6, 0.02}, {0.1, 0.7, 0.02}},
                    {{-0.1, 0.8, 0.05}, {0.1, 0.9, 0.3}});
}

Reach::Reach(ReachVariant variant, SawyerOptions options)
    : SawyerTask(Config(variant), options), variant_(variant) {}

RewardTerms Reach::Info(double tcp_to_goal) const {
  RewardTerms terms;
  terms.success = tcp_to_goal <= 0.05;
  terms.obj_to_target = tcp_to_goal;
  if (variant_ == ReachVariant::kOpen) {  // v3's reach-wall reports these as 0
    terms.near_object = tcp_to_goal;
    terms.grasp_success = 1.0;
    terms.grasp_reward = tcp_to_goal;
  }
  return terms;
}

RewardTerms Reach::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double tcp_to_goal = Distance(s.tcp, s.goal);
  const double in_place = LongTailTolerance(tcp_to_goal, 0.0, 0.05, Distance(s.hand_init, s.goal));
  RewardTerms terms = Info(tcp_to_goal);
  terms.reward = 10.0 * in_place;
  terms.in_place_reward = in_place;
  return terms;
}

void Reach::InitTaskState(SawyerState& s) const { s.v1_max_dist = Distance(s.tcp_init, s.goal); }

RewardTerms Reach::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  // v3's evaluate_state on v1's (reward, distance, 0)
  RewardTerms terms = Info(Distance(s.tcp, s.goal));
  terms.reward = std::max(v1::Progress(s.v1_max_dist, terms.obj_to_target), 0.0);
  return terms;
}

void ReachScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                              std::span<float> action) {
  const SawyerObs o(env_obs);
  // The fingers hang below the tcp: keep it above the wall until past it.
  const bool over_wall = variant_ == ReachVariant::kWall && o.tcp[1] < wall::kWallFarY + 0.03;
  const Vec3 target = over_wall ? Vec3{o.goal[0], o.goal[1], std::max(o.goal[2], wall::kOverWall)}
                                : o.goal;
  MoveTo(o.hand, {target[0], target[1], target[2] + kTcpBelowHand}, -1.0, action);
}

}  // namespace manyworlds::manipulation
