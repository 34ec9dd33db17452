// Our MJCF of dm_control's finger, cheetah and walker domains, written for manyworlds from the
// facts in docs/reference/dmc_hipbmdp.md (section 2.5): geometry, joint ranges, stiffness,
// damping, armature, gears, contact settings, timesteps. Angles are in radians. Each model's
// first camera mirrors dm_control's camera 0 of that domain (MTEnv renders camera 0):
//   finger   "fixed": at (0, -1, 0.8), looking along +y and 26.6 degrees down;
//   cheetah  "side":  3 m to the side of the torso, level, following the centre of mass;
//   walker   "side":  2 m to the side and 0.7 m above the torso origin, 30 degrees down,
//                     following the centre of mass.
// Left out (nothing reads them in these tasks): finger's target site and second camera,
// the "back" cameras, the skybox and floor textures (plain colours instead).
//
// The parameters are the HiP-BMDP variants' physical quantities (MTEnv's variant files each
// change one of them); the defaults are dm_control's values.
#ifndef MANYWORLDS_DMC_MODELS_H_
#define MANYWORLDS_DMC_MODELS_H_

#include <mujoco/mujoco.h>

#include <memory>
#include <string>
#include <string_view>

namespace manyworlds::dmc {

struct FingerParams {
  // First semi-axis of the two touch-sensor ellipsoids on the fingertip (m). Sites have no
  // mass and do not collide: this changes only which contacts the touch sensors count.
  double touch_site_x = 0.025;
};

struct CheetahParams {
  // Half-length of the torso capsule (m); the hips stay at x = -0.5 and 0.5. The model's
  // total mass is fixed at 14 kg, so a longer torso takes mass from the legs.
  double torso_half_length = 0.5;
};

struct WalkerParams {
  // Sliding friction of every geom, the floor included (MuJoCo uses the larger of the two
  // geoms' coefficients in a contact).
  double friction = 0.7;
  // Half-length of the left foot's capsule (m); the right foot keeps 0.1.
  double left_foot_half_length = 0.1;
};

std::string FingerXml(const FingerParams& params = {});
std::string CheetahXml(const CheetahParams& params = {});
std::string WalkerXml(const WalkerParams& params = {});

// An MJCF document and its compiled model.
struct CompiledMjcf {
  std::string xml;
  std::shared_ptr<const mjModel> model;
};

// `xml` compiled once per process and shared (read-only) by every env that asks for the same
// document; the reference stays valid for the life of the process. Thread-safe. Throws
// MujocoError.
const CompiledMjcf& CompiledModel(const std::string& xml, std::string_view name);

}  // namespace manyworlds::dmc

#endif  // MANYWORLDS_DMC_MODELS_H_
