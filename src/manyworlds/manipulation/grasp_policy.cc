#include "manyworlds/manipulation/grasp_policy.h"

#include <cmath>

#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

void GraspAndCarry(const SawyerObs& o, const Vec3& carry_to, std::span<float> action) {
  GraspAndCarry(o, carry_to, action, GraspParams{});
}

void GraspAndCarry(const SawyerObs& o, const Vec3& carry_to, std::span<float> action,
                   const GraspParams& p) {
  const Vec3& obj = o.obj1;
  const auto hand_for_tcp = [](const Vec3& tcp) {
    return Vec3{tcp[0], tcp[1], tcp[2] + kTcpBelowHand};
  };
  if (Distance(o.tcp, obj) < p.held_distance && o.gripper_opening < p.closed_on_object) {
    MoveTo(o.hand, hand_for_tcp(carry_to), 1.0, action);
    return;
  }
  const double xy_error = std::hypot(o.tcp[0] - obj[0], o.tcp[1] - obj[1]);
  if (xy_error > p.over_object_xy) {
    MoveTo(o.hand, hand_for_tcp({obj[0], obj[1], obj[2] + p.approach_height}), -1.0, action);
  } else if (o.tcp[2] - obj[2] > p.at_grasp_height) {
    MoveTo(o.hand, hand_for_tcp(obj), -1.0, action);
  } else {
    MoveTo(o.hand, hand_for_tcp(obj), 1.0, action);
  }
}

void GraspAndCarryOver(const SawyerObs& o, const Vec3& carry_to, double clearance, double over_xy,
                       std::span<float> action, const GraspParams& p) {
  const Vec3& obj = o.obj1;
  Vec3 via = carry_to;
  if (std::hypot(obj[0] - carry_to[0], obj[1] - carry_to[1]) > over_xy) {
    // 1 cm short of the clearance height counts as up.
    const bool up = obj[2] > clearance - 0.01;
    via = up ? Vec3{carry_to[0], carry_to[1], clearance} : Vec3{obj[0], obj[1], clearance};
  }
  GraspAndCarry(o, via, action, p);
}

}  // namespace manyworlds::manipulation
