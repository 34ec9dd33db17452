// peg-unplug-side: pull a plug out of the socket in a low wall, along +x
// (Meta-World v3, reward version "v2").
//   wall (v3's box) obj_pos in (-0.25, 0.6, -0.001)-(-0.15, 0.8, 0.001);
//     the plug sits in its socket at obj_pos + (0.044, 0, 0.131)
//     (assets/peg_unplug_side.xml); goal = obj_pos + (0.194, 0, 0.131),
//     0.15 m out along x from the plug; hand starts at (0, 0.6, 0.2), bounds
//     (-0.5, 0.4, 0.05)-(0.5, 1, 0.5) (all as v3)
//   object point (obs[4:7]): the plug's end, 0.04 m along it (v3's site
//     pegEnd), obj_pos + (0.084, 0, 0.131) seated; obs[7:11] the plug's
//     (w, x, y, z) (1, 0, 0, 0); obj_init = the object point at reset (v3's
//     obj_init_pos), 0.11 m from the goal
//   grasped = gripper caging of the plug's end (high density; obj radius
//     0.025, pad 0.05, reach 0.01, xz 0.005, effort 0.8)
//   in_place = tol(|obj - goal|, (0, 0.05), margin |obj_init - goal|)
//   pulling = opening obs[3] > 0.5 and the end moved 0.015 m along +x
//   reward = 2 grasped; 1 + 2 grasped + 5 in_place while pulling with the
//     tcp within 0.035 m of the end; 10 once |obj - goal| <= 0.05
//   info: success |obj - goal| <= 0.07 (pulled 4 cm); near_object
//     |tcp - obj| <= 0.03; grasp_success pulling; grasp_reward grasped;
//     in_place_reward in_place; obj_to_target |obj - goal|.
//   (tol: long-tail tolerance.)
// Our plug slides along x on a joint held by dry friction where v3's is a
// free body wedged in its socket: the same 4 cm pull succeeds (the asset
// says why).
//   v1: reach (xy first, the tcp's height change from the hand start weighted
//     2; + max(a[3], 0) / 50 within 5 cm) + max(progress(xy distance to the
//     goal), 0) within 5 cm, max_dist = |goal - obj_init| (maxPlacingDist);
//     info from v1's zeros: success xy distance <= 0.07, near_object 1.
#ifndef MANYWORLDS_MANIPULATION_PEG_PEG_UNPLUG_SIDE_H_
#define MANYWORLDS_MANIPULATION_PEG_PEG_UNPLUG_SIDE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class PegUnplugSide : public SawyerTask {
 public:
  explicit PegUnplugSide(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  // goal = obj + (0.194, 0, 0.131).
  Vec3 DeriveGoal(const Vec3& obj, const Vec3& drawn_goal) const override;
  void PlaceObjects(mjModel* m, mjData* d) override;
  void RefreshTaskState(const mjData* d, SawyerState& state) const override;
  // obj_init = the plug's end at reset.
  void InitTaskState(SawyerState& state) const override;

 private:
  int box_ = -1;      // body: the wall
  int plug_end_ = -1;  // site: the object point
};

// Closes the fingers round the plug's block from above, 2 cm behind its
// end, and pulls it out along +x to the goal.
class PegUnplugSideScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PEG_PEG_UNPLUG_SIDE_H_
