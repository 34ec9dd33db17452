#include "manyworlds/manipulation/pick_place/pick_place_wall.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/manipulation/wall.h"

namespace manyworlds::manipulation {

SawyerTaskConfig PickPlaceWall::Config() {
  return wall::WallConfig("pick-place-wall",
                          "Sawyer arm: carry a puck over a wall to a goal in the air",
                          "pick_place_wall.xml", 0.05, 0.3);
}

PickPlaceWall::PickPlaceWall(SawyerOptions options) : SawyerTask(Config(), options) {}

RewardTerms PickPlaceWall::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  constexpr double kRadius = 0.05;
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double obj_to_target = Distance(s.obj, s.goal);
  // over the wall, z counting thrice
  const double to_midpoint =
      wall::TowardMidpoint(s, {s.goal[0], 0.77, 0.25}, {1.0, 1.0, 3.0}, kRadius);
  const double to_goal = TowardGoal(s, obj_to_target, kRadius);
  const CagingParams caging{};  // v3's defaults, not high-density
  const double grasped = CageObject(s, s.obj, action[3], caging);
  const double grasped_to_midpoint = HamacherProduct(grasped, to_midpoint);

  double reward = grasped_to_midpoint;
  if (tcp_to_obj < 0.02 && s.gripper_opening > 0 && s.obj[2] - 0.015 > s.obj_init[2]) {
    reward = s.obj[1] > 0.75 ? grasped_to_midpoint + 5.0 + 3.0 * to_goal
                             : grasped_to_midpoint + 1.0 + 4.0 * to_midpoint;
  }
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target < kRadius,
                               .obj_to_target = obj_to_target, .success_radius = 0.07,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = to_goal});
}

void PickPlaceWall::InitTaskState(SawyerState& s) const {
  v1::InitPickPlace(s, s.obj_init[2], 0.04);  // v3's liftThresh
}

RewardTerms PickPlaceWall::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  return v1::PickPlaceStep(s, action[3], 0.07);
}

void PickPlaceWallScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                      std::span<float> action) {
  const SawyerObs o(env_obs);
  wall::CarryOverWall(o, o.goal, action);
}

}  // namespace manyworlds::manipulation
