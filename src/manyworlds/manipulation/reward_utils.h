// Shaped-reward primitives shared by the Sawyer tasks (Meta-World v3's
// metaworld/utils/reward_utils.py and SawyerXYZEnv._gripper_caging_reward):
// long-tail and gaussian tolerances, the Hamacher product, and the
// gripper-caging term.
// All return values lie in [0, 1].
#ifndef MANYWORLDS_MANIPULATION_REWARD_UTILS_H_
#define MANYWORLDS_MANIPULATION_REWARD_UTILS_H_

#include <array>

namespace manyworlds::manipulation {

using Vec3 = std::array<double, 3>;

double Distance(const Vec3& a, const Vec3& b);

// 1 inside [low, high]. Outside, with d = distance to the nearer bound
// divided by `margin`, returns 1 / (9 d^2 + 1): the long-tail sigmoid scaled
// to be 0.1 at d = 1. With margin == 0 it is 0 outside the bounds.
double LongTailTolerance(double x, double low, double high, double margin);

// 1 inside [low, high]. Outside, with d as above, returns 0.1^(d^2) =
// exp(-(d s)^2 / 2) with s^2 = -2 ln 0.1: the gaussian sigmoid scaled to be
// 0.1 at d = 1. With margin == 0 it is 0 outside the bounds.
double GaussianTolerance(double x, double low, double high, double margin);

// Hamacher t-norm a b / (a + b - a b); 0 when both are 0. Inputs in [0, 1]
// (values outside are clamped).
double HamacherProduct(double a, double b);

// Meta-World's prism tolerance: inside the axis-aligned box with corners
// `zero` and `one`, the product over axes of (x - zero) / (one - zero)
// (0 at the `zero` corner, 1 at `one`); 1 outside the box.
double RectPrismTolerance(const Vec3& x, const Vec3& zero, const Vec3& one);

// Geometry the caging reward reads: current positions and the episode's
// initial ones.
struct CagingInputs {
  Vec3 left_pad;   // finger pad centres (fingers close along y)
  Vec3 right_pad;
  Vec3 tcp;        // midpoint of the pads
  Vec3 obj;        // object position
  Vec3 obj_init;   // object position at reset
  Vec3 tcp_init;   // tcp at reset
  double gripper_action = 0;  // action[3]
};

struct CagingParams {
  double obj_radius = 0.015;          // pads closer than this to the object centre are "inside" it
  double pad_success_thresh = 0.05;   // y distance under which a pad cages the object
  double object_reach_radius = 0.01;  // medium density: tcp-object distance counted as reached
  double xz_thresh = 0.005;           // tcp-object distance in xz counted as aligned
  double desired_gripper_effort = 1.0;
  bool high_density = false;    // result (H(caging, gripping) + caging) / 2
  bool medium_density = false;  // result (H(caging, gripping) + reach) / 2
};

// The gripper-caging reward (v3's SawyerXYZEnv._gripper_caging_reward): high when the pads bracket
// the object along y, the tcp is aligned with it in xz, and the gripper is
// commanded closed.
double GripperCagingReward(const CagingInputs& in, const CagingParams& params);

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_REWARD_UTILS_H_
