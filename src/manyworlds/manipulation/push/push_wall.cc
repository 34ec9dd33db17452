#include "manyworlds/manipulation/push/push_wall.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/manipulation/wall.h"

namespace manyworlds::manipulation {

SawyerTaskConfig PushWall::Config() {
  SawyerTaskConfig config = wall::WallConfig(
      "push-wall", "Sawyer arm: push a puck past a wall to a goal on the table", "push_wall.xml",
      0.01, 0.02);
  config.goal_z_at_object = true;
  return config;
}

PushWall::PushWall(SawyerOptions options) : SawyerTask(Config(), options) {}

RewardTerms PushWall::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  constexpr double kRadius = 0.05;
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double obj_to_target = Distance(s.obj, s.goal);
  // past the wall's end, x counting thrice
  const double to_midpoint =
      wall::TowardMidpoint(s, {-0.05, 0.77, s.obj[2]}, {3.0, 1.0, 1.0}, kRadius);
  const double to_goal = TowardGoal(s, obj_to_target, kRadius);
  const CagingParams caging{.high_density = true};
  const double grasped = CageObject(s, s.obj, action[3], caging);

  double reward = 2.0 * grasped;
  if (tcp_to_obj < 0.02 && s.gripper_opening > 0) {
    reward = s.obj[1] > 0.75 ? 2.0 * grasped + 5.0 + 3.0 * to_goal
                             : 2.0 * grasped + 1.0 + 4.0 * to_midpoint;
  }
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target < kRadius,
                               .obj_to_target = obj_to_target, .success_radius = 0.07,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = to_goal});
}

void PushWall::InitTaskState(SawyerState& s) const { v1::InitPush(s); }

RewardTerms PushWall::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return v1::PushStep(s, 0.07);
}

void PushWallScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                 std::span<float> action) {
  const SawyerObs o(env_obs);
  wall::CarryOverWall(o, {o.goal[0], o.goal[1], o.goal[2] + 0.005}, action);
}

}  // namespace manyworlds::manipulation
