#include "manyworlds/manipulation/policy_utils.h"

#include <algorithm>

#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

SawyerObs::SawyerObs(std::span<const float> obs) {
  for (int i = 0; i < 3; ++i) {
    hand[i] = obs[kObsHand + i];
    obj1[i] = obs[kObsObj1Pos + i];
    goal[i] = obs[kObsGoal + i];
  }
  gripper_opening = obs[kObsGripper];
  tcp = {hand[0], hand[1], hand[2] - kTcpBelowHand};
}

void MoveTo(const Vec3& hand, const Vec3& target, double grip, std::span<float> action,
            double gain) {
  for (int i = 0; i < 3; ++i) {
    action[i] = static_cast<float>(std::clamp(gain * (target[i] - hand[i]), -1.0, 1.0));
  }
  action[3] = static_cast<float>(std::clamp(grip, -1.0, 1.0));
}

}  // namespace manyworlds::manipulation
