// bin-picking (Meta-World v3, reward version "v2"): pick the cube out of
// bin A and put it in bin B.
//   cube obj_pos in (-0.21, 0.65, 0.03)-(-0.03, 0.75, 0.03): v3 draws xy
//     from this range and keeps the cube's resting height, 0.03, as
//     obj_init_pos (its drawn z, 0.02, is never used); goal fixed at bin
//     B's origin (0.12, 0.7, 0) (v3's bin_goal body; the drawn goal is
//     never used); hand starts at (0, 0.6, 0.2), bounds
//     (-0.5, 0.4, 0.07)-(0.5, 1, 0.5) (all as v3)
//   bins (assets/bin_picking.xml): bin B as v3's; bin A 4 cm wider inside
//     in x so that every start is at rest (v3 starts the cube inside bin
//     A's x walls at the range's ends)
//   obs[4:7] the cube's centre, obs[7:11] its (w, x, y, z) (v3's xquat)
//   in_place = tol(|obj - goal|, (0, 0.05), margin obj_to_target_init),
//     v3's _target_to_obj_init: |obj - goal| at the first step (the cube
//     at rest: |obj_init - goal|)
//   floor = min over the funnels at obj_init and at the goal (hand xy
//     distance r to each): 0 within 3 cm, else 0.02 ln(r - 0.03) + 0.2;
//     above_floor = 1 when hand z >= floor, else tol(floor - hand z,
//     (0, 0.01), margin 0.05)
//   grasped = gripper caging (high density; obj radius 0.015, pad 0.05,
//     reach 0.01, xz 0.01, gripper effort 0.7)
//   held = |hand - obj| < 0.04, opening >= 0.43 and the cube 2 cm above
//     obj_init
//   reward = H(grasped, in_place); + 1 + 5 H(above_floor, in_place) while
//     held; 10 once |obj - goal| < 0.05
//   info: success |obj - goal| <= 0.05 (the cube in bin B, within 4 cm of
//     its centre in xy); near_object |hand - obj| < 0.04; grasp_success
//     held; grasp_reward grasped; in_place_reward in_place; obj_to_target
//     |obj - goal|.
//   The hand (obs[0:3]) is 3.5 cm above our tcp, 4.5 cm above v3's, so
//   "hand within 4 cm of the cube" is the grip height in both. Our opening
//   is 0.5 closed on the cube and 0.2 closed on nothing: opening < 0.43
//   means shut without it, as in v3.
//   v1 (reward_version=v1): pick-place's reach, lift and place terms with
//   v3's bin-picking changes: the placing distance is planar (to bin B's
//   origin), the reach goes xy-first beyond 6 cm (tcp height change
//   weighted 1), lift target 10 cm above the cube's start, normaliser
//   |obj_init.xy - goal.xy| + lift target; with the cube within 5 cm of
//   bin B's origin in x and y, -200 a[3] is added (open to release), and
//   once it also rests low (below its start height + 5 cm) the reward is
//   that plus the place bonus alone. success: planar distance <= 0.05;
//   obj_to_target the planar distance; the other info fields 0 (as v3).
#ifndef MANYWORLDS_MANIPULATION_CONTAINER_BIN_PICKING_H_
#define MANYWORLDS_MANIPULATION_CONTAINER_BIN_PICKING_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class BinPicking : public SawyerTask {
 public:
  explicit BinPicking(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Grasps the cube (with the fingers at least 2.5 cm from bin A's y walls:
// closing drags it), lifts it over the walls and lowers it into bin B.
class BinPickingScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_CONTAINER_BIN_PICKING_H_
