// assembly, disassemble: a round nut with a handle, put onto a peg or lifted
// off it (Meta-World v3, reward version "v2"). The nut and the peg are
// assets/nut_peg_fixture.xml (v3's sizes); the nut lies flat, turned 90
// degrees about z at reset as v3's, its handle 0.13 m along +x from the
// ring's centre.
//   object point (obs[4:7]): the handle's centre (v3's site RoundNut-8);
//     obs[7:11] the nut's (w, x, y, z), (0.7071, 0, 0, 0.7071) lying flat;
//     the record's obj_head is the ring's centre (v3's site RoundNut),
//     obj_quat obs[7:11]
//   hand starts at (0, 0.6, 0.2) (assembly), (0, 0.4, 0.2) (disassemble);
//     bounds (-0.5, 0.4, 0.05)-(0.5, 1, 0.5)
// Both rewards:
//   quat = max(1 - |obs[7:11] - (0.707, 0, 0, 0.707)| / 0.4, 0): lying flat
//   handle = obs[4:7] with its x set to the hand's while they are within
//     0.01 m in x (v3's "wrench_threshed": the handle is long in x)
//   grab = gripper caging of `handle` (obj radius 0.015, pad 0.02, reach
//     0.01, xz 0.01; medium density for assembly, high for disassemble)
//   reward = (2 grab + 6 in_place) quat, 10 on success
//   info: near_object quat; grasp_success grab >= 0.5; grasp_reward grab;
//     in_place_reward in_place; obj_to_target 0 (all as v3).
// assembly:
//   nut at (0, 0.6, 0.02); goal (v3's pegTop, the peg's top) in
//     (-0.1, 0.75, 0.1)-(0.1, 0.85, 0.1); the peg (0.1 m tall) stands on
//     the table under it; v3's 0.1 m nut-goal rule never binds
//   e = goal - ring centre, r = |e_xy|; success r < 0.02 and e_z > 0: the
//     ring round the peg, its centre below the top
//   funnel: height h = 0.02 ln(r - t) + 0.2 when r > t (t = 0.02 on success,
//     else 0.01), else 0; in_place = 0.1 [ring z > 0.02 or r < t]
//     + 0.9 tol(|(e_x, e_y, 3 (h - ring z))|, (0, 0.02), margin 0.4)
// disassemble:
//   nut in (0, 0.6, 0.025)-(0.1, 0.75, 0.02501), round the peg, whose top
//     is 0.08 above it; goal = nut + (0, 0, 0.15); v3 draws a goal in
//     (-0.1, 0.6, 0.17)-(0.1, 0.75, 0.17) only to redraw both while it is
//     within 0.1 m (xy) of the nut, then drops it: we draw the same way.
//     The observation bounds the goal by v3's goal_space, (-0.1, 0.6,
//     0.1749)-(0.1, 0.75, 0.1751): x from -0.1 where the goals start at 0
//   success: the handle above the goal (obs[6] > goal z): lifted 0.15 m,
//     the ring clear of the peg's top
//   in_place = 0.1 [ring z > 0.02] + 0.9 tol(|goal + (0, 0, 0.1) - ring|,
//     (0, 0.02), margin 0.2)
// (tol: long-tail tolerance.)
// v1 (reward_version=v1), both on the handle (obs[4:7]) for the reach
// (xy-first beyond 4 cm; finger-closing incentive within 4 cm) and on the
// ring's centre for lift and place; info fields 0 (as v3):
//   assembly: lift target v3's obj_height + 0.1 (obj_height the handle's
//     height at reset, 0.0199455: v3 places its nut 1 mm above the rest
//     pose ours starts in); held = ring at the lift target with the tcp
//     within 3 cm of the handle; placing distance planar, to the peg's top;
//     over the peg (3 cm in x and y) the lift bonus is full and the place
//     bonus adds 2000 (lift target - s) + 2000 (exp(-s^2 / 0.003) +
//     exp(-s^2 / 0.0003)), s = |ring z - obj_height|; success: over the
//     peg with s <= 0.04
//   disassemble: lift target the nut's start height + 0.05; placing
//     distance |handle - goal|; the place bonus needs the tcp within 3 cm
//     of the handle; once the ring is 5 cm off the peg's axis in x or y the
//     reach term is 0 and the lift bonus full; success obs[6] > goal z
#ifndef MANYWORLDS_MANIPULATION_PEG_NUT_H_
#define MANYWORLDS_MANIPULATION_PEG_NUT_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

// The nut-and-peg scene: places the turned nut and the peg, and fills the
// record's object point (the handle) and obj_head (the ring's centre).
class NutTask : public SawyerTask {
 protected:
  // peg_below_goal: the peg's centre is this far below the goal.
  NutTask(SawyerTaskConfig config, double peg_below_goal, SawyerOptions options);
  void PlaceObjects(mjModel* m, mjData* d) override;
  void RefreshTaskState(const mjData* d, SawyerState& state) const override;

 private:
  double peg_below_goal_;
  int nut_qpos_ = -1;    // the nut's free joint
  int peg_ = -1;         // body
  int handle_ = -1;      // site: the object point
  int nut_centre_ = -1;  // site
};

class Assembly : public NutTask {
 public:
  explicit Assembly(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

class Disassemble : public NutTask {
 public:
  explicit Disassemble(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
  TaskState DoSampleTaskState(Rng& task_rng) override;
  // goal = obj + (0, 0, 0.15).
  Vec3 DeriveGoal(const Vec3& obj, const Vec3& drawn_goal) const override;
};

// Grasps the handle, lifts the nut above the peg, brings the ring's centre
// (found from the handle and the nut's orientation) over the peg's axis and
// lowers it round the peg.
class AssemblyScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

// Grasps the handle and lifts the nut straight up off the peg.
class DisassembleScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PEG_NUT_H_
