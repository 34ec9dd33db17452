#include "manyworlds/manipulation/reach/reach.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/policy_utils.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {

SawyerTaskConfig Reach::Config() {
  SawyerTaskConfig config;
  config.id = "reach";
  config.description = "Sawyer arm: move the gripper to a goal position in space";
  config.xml_file = "reach.xml";
  config.obj_low = {-0.1, 0.6, 0.02};
  config.obj_high = {0.1, 0.7, 0.02};
  config.goal_low = {-0.1, 0.8, 0.05};
  config.goal_high = {0.1, 0.9, 0.3};
  return config;
}

Reach::Reach(SawyerOptions options) : SawyerTask(Config(), options) {}

RewardTerms Reach::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double tcp_to_goal = Distance(s.tcp, s.goal);
  const double in_place = LongTailTolerance(tcp_to_goal, 0.0, 0.05, Distance(s.hand_init, s.goal));
  RewardTerms terms;
  terms.reward = 10.0 * in_place;
  terms.success = tcp_to_goal <= 0.05;
  terms.near_object = tcp_to_goal;
  terms.grasp_success = 1.0;
  terms.grasp_reward = tcp_to_goal;
  terms.in_place_reward = in_place;
  terms.obj_to_target = tcp_to_goal;
  return terms;
}

void Reach::InitTaskState(SawyerState& s) const { s.v1_max_dist = Distance(s.tcp_init, s.goal); }

RewardTerms Reach::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double tcp_to_goal = Distance(s.tcp, s.goal);
  RewardTerms terms;
  terms.reward = std::max(v1::Progress(s.v1_max_dist, tcp_to_goal), 0.0);
  terms.success = tcp_to_goal <= 0.05;
  terms.near_object = tcp_to_goal;
  terms.grasp_success = 1.0;
  terms.grasp_reward = tcp_to_goal;
  terms.in_place_reward = 0.0;
  terms.obj_to_target = tcp_to_goal;
  return terms;
}

void ReachScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                              std::span<float> action) {
  const SawyerObs o(env_obs);
  MoveTo(o.hand, {o.goal[0], o.goal[1], o.goal[2] + kTcpBelowHand}, -1.0, action);
}

}  // namespace manyworlds::manipulation
