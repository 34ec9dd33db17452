// Helpers for the scripted policies: read the 39-value observation and turn
// a desired hand position into an action.
#ifndef MANYWORLDS_MANIPULATION_POLICY_UTILS_H_
#define MANYWORLDS_MANIPULATION_POLICY_UTILS_H_

#include <span>

#include "manyworlds/manipulation/reward_utils.h"

namespace manyworlds::manipulation {

// Fields of a 39-value observation (layout in sawyer_task.h).
struct SawyerObs {
  Vec3 hand{};
  double gripper_opening = 0;
  Vec3 obj1{};
  Vec3 goal{};
  Vec3 tcp{};  // hand minus the fixed tcp offset

  explicit SawyerObs(std::span<const float> obs);
};

// Proportional move: a[0:3] = clip(gain * (target - hand), -1, 1), where an
// action unit is one centimetre; a[3] = grip.
void MoveTo(const Vec3& hand, const Vec3& target, double grip, std::span<float> action,
            double gain = 25.0);

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_POLICY_UTILS_H_
