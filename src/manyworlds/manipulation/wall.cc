#include "manyworlds/manipulation/wall.h"

#include <algorithm>
#include <utility>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"

namespace manyworlds::manipulation::wall {

SawyerTaskConfig WallConfig(std::string id, std::string description, std::string xml_file,
                            double goal_z_low, double goal_z_high) {
  // v3 draws the puck at z 0.015; ours rests at its half-height, 0.02.
  return TaskConfig(std::move(id), std::move(description), std::move(xml_file),
                    {{-0.05, 0.6, 0.02}, {0.05, 0.65, 0.02}},
                    {{-0.05, 0.85, goal_z_low}, {0.05, 0.9, goal_z_high}});
}

double TowardMidpoint(const SawyerState& s, const Vec3& midpoint, const Vec3& weights,
                      double radius) {
  return LongTailTolerance(WeightedDistance(s.obj, midpoint, weights), 0.0, radius,
                           WeightedDistance(s.obj_init, midpoint, weights));
}

void CarryOverWall(const SawyerObs& o, const Vec3& goal, std::span<float> action) {
  const Vec3& puck = o.obj1;
  const bool before_wall = puck[1] < kWallFarY + 0.03;
  Vec3 carry_to;
  if (before_wall && puck[2] < kOverWall - 0.01) {
    carry_to = {puck[0], puck[1], kOverWall + 0.01};  // straight up first
  } else if (before_wall) {
    carry_to = {goal[0], goal[1], kOverWall + 0.01};  // across, above the wall
  } else {
    carry_to = goal;
  }
  GraspAndCarry(o, carry_to, action);
}

}  // namespace manyworlds::manipulation::wall
