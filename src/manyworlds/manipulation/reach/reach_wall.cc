#include "manyworlds/manipulation/reach/reach_wall.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/policy_utils.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/manipulation/wall.h"

namespace manyworlds::manipulation {

SawyerTaskConfig ReachWall::Config() {
  SawyerTaskConfig config = wall::WallConfig(0.05, 0.3);
  config.id = "reach-wall";
  config.description = "Sawyer arm: reach a goal behind a wall";
  config.xml_file = "reach_wall.xml";
  return config;
}

ReachWall::ReachWall(SawyerOptions options) : SawyerTask(Config(), options) {}

RewardTerms ReachWall::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double tcp_to_goal = Distance(s.tcp, s.goal);
  const double in_place = LongTailTolerance(tcp_to_goal, 0.0, 0.05, Distance(s.hand_init, s.goal));
  RewardTerms terms;
  terms.reward = 10.0 * in_place;
  terms.success = tcp_to_goal <= 0.05;
  terms.in_place_reward = in_place;
  terms.obj_to_target = tcp_to_goal;
  return terms;
}

void ReachWall::InitTaskState(SawyerState& s) const { s.v1_max_dist = Distance(s.tcp_init, s.goal); }

RewardTerms ReachWall::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double tcp_to_goal = Distance(s.tcp, s.goal);
  RewardTerms terms;
  terms.reward = std::max(v1::Progress(s.v1_max_dist, tcp_to_goal), 0.0);
  // v3's evaluate_state on v1's (reward, distance, 0)
  terms.success = tcp_to_goal <= 0.05;
  terms.obj_to_target = tcp_to_goal;
  return terms;
}

void ReachWallScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const SawyerObs o(env_obs);
  // The fingers hang below the tcp: keep it above the wall until past it.
  const bool before_wall = o.tcp[1] < wall::kWallFarY + 0.03;
  const Vec3 target = before_wall ? Vec3{o.goal[0], o.goal[1], std::max(o.goal[2], wall::kOverWall)}
                                  : o.goal;
  MoveTo(o.hand, {target[0], target[1], target[2] + kTcpBelowHand}, -1.0, action);
}

}  // namespace manyworlds::manipulation
