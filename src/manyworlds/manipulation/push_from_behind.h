// The slide family's scripted motion: fingers closed into a paddle, rise,
// come down behind the object (on the side away from the target), then
// push it toward the target. Stateless: every step decides from the
// observation.
#ifndef MANYWORLDS_MANIPULATION_PUSH_FROM_BEHIND_H_
#define MANYWORLDS_MANIPULATION_PUSH_FROM_BEHIND_H_

#include <span>

#include "manyworlds/manipulation/policy_utils.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

struct PushParams {
  double low = 0.015;    // tcp height while pushing
  double high = 0.08;    // tcp height while travelling
  double behind = 0.08;  // tcp distance behind the object's centre
};

void PushFromBehind(const SawyerObs& obs, const Vec3& object, const Vec3& target,
                    const PushParams& params, std::span<float> action);

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PUSH_FROM_BEHIND_H_
