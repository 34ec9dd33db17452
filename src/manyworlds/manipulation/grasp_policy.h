// The grasp-and-carry script shared by push and pick-place: a stateless
// function of the observation (so an episode can start anywhere).
#ifndef MANYWORLDS_MANIPULATION_GRASP_POLICY_H_
#define MANYWORLDS_MANIPULATION_GRASP_POLICY_H_

#include <span>

#include "manyworlds/manipulation/policy_utils.h"

namespace manyworlds::manipulation {

// Phases, chosen from the observation each step:
//  1. object held (closed on it, tcp at it): carry it, tcp toward `carry_to`;
//  2. hand not over the object: move above it, gripper open;
//  3. over it but high: descend to grasp height, gripper open;
//  4. at grasp height: close the gripper in place.
void GraspAndCarry(const SawyerObs& obs, const Vec3& carry_to, std::span<float> action);

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_GRASP_POLICY_H_
