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

// Thresholds of the script; the defaults (used by the overload above) suit
// the 4 cm puck: the opening closed on it is about 0.5, open is 1.
struct GraspParams {
  double closed_on_object = 0.55;  // opening below which the pads hold it
  double held_distance = 0.025;    // tcp-object distance while held
  double over_object_xy = 0.012;   // xy alignment before descending
  double approach_height = 0.08;   // tcp above the object on approach
  double at_grasp_height = 0.006;  // tcp-object height error to close at
};

// The same script with other thresholds (larger or thinner objects).
void GraspAndCarry(const SawyerObs& obs, const Vec3& carry_to, std::span<float> action,
                   const GraspParams& params);

// GraspAndCarry over obstacles (hole and bin edges): while the object is
// more than `over_xy` from carry_to in xy, it is carried at tcp height
// `clearance`, first straight up from where it is, then across; once over
// carry_to it goes straight there (down into a hole or bin, or up).
void GraspAndCarryOver(const SawyerObs& obs, const Vec3& carry_to, double clearance,
                       double over_xy, std::span<float> action,
                       const GraspParams& params = GraspParams{});

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_GRASP_POLICY_H_
