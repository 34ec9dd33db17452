#include "manyworlds/manipulation/grasp_policy.h"

#include <cmath>

#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {
namespace {

// Opening with the pads closed on the 4 cm puck is about 0.5; open is 1.
constexpr double kClosedOnObject = 0.55;
constexpr double kHeldDistance = 0.025;   // tcp-object distance while held
constexpr double kOverObjectXy = 0.012;   // xy alignment before descending
constexpr double kApproachHeight = 0.08;  // tcp above the object on approach
constexpr double kAtGraspHeight = 0.006;

}  // namespace

void GraspAndCarry(const SawyerObs& o, const Vec3& carry_to, std::span<float> action) {
  const Vec3& obj = o.obj1;
  const auto hand_for_tcp = [](const Vec3& tcp) {
    return Vec3{tcp[0], tcp[1], tcp[2] + kTcpBelowHand};
  };
  if (Distance(o.tcp, obj) < kHeldDistance && o.gripper_opening < kClosedOnObject) {
    MoveTo(o.hand, hand_for_tcp(carry_to), 1.0, action);
    return;
  }
  const double xy_error = std::hypot(o.tcp[0] - obj[0], o.tcp[1] - obj[1]);
  if (xy_error > kOverObjectXy) {
    MoveTo(o.hand, hand_for_tcp({obj[0], obj[1], obj[2] + kApproachHeight}), -1.0, action);
  } else if (o.tcp[2] - obj[2] > kAtGraspHeight) {
    MoveTo(o.hand, hand_for_tcp(obj), -1.0, action);
  } else {
    MoveTo(o.hand, hand_for_tcp(obj), 1.0, action);
  }
}

}  // namespace manyworlds::manipulation
