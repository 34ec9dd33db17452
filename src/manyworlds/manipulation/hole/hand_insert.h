// hand-insert (Meta-World v3, reward version "v2"): push the block over the
// raised table top into the hole.
//   block obj_pos in (-0.1, 0.6, 0.05)-(0.1, 0.7, 0.05); goal in
//     (-0.04, 0.8, -0.0201)-(0.04, 0.88, -0.0199), >= 0.15 m from the
//     block in xy; hand starts at (0, 0.6, 0.2), bounds
//     (-0.5, 0.4, -0.15)-(0.5, 1, 0.5) (all as v3)
//   table (assets/hand_insert.xml, v3's sawyer_table_with_hole): top at
//     z = 0.05, hole x in [-0.08, 0.08], y in [0.76, 0.92], floor z = 0.
//     v3 puts the block at obj_pos, 2 cm into the top, and lets the
//     contact push it up to rest at z 0.07 during the first 20 steps; we
//     put it at rest there (obj_pos + (0, 0, 0.02)). obj_init stays
//     obj_pos, as v3's obj_init_pos. A block on the hole floor is at
//     z 0.02, 4 cm above the goal, so success needs it within 3 cm of the
//     goal in xy (v3's scripted policy presses it 1 cm into the floor).
//   obs[4:7] the block's centre, obs[7:11] its (w, x, y, z) (v3's xquat)
//   in_place = tol(|obj - goal|, (0, 0.05), margin |obj_init - goal|)
//   grasped = gripper caging (high density; obj radius 0.015, pad 0.05,
//     reach 0.01, xz 0.005)
//   reward = H(grasped, in_place); + 1 + 7 in_place while |tcp - obj| < 0.02
//     and opening > 0; 10 once |obj - goal| < 0.05
//   info: success |obj - goal| <= 0.05; near_object |tcp - obj| <= 0.03;
//     grasp_success = touching, opening > 0 and the block 2 cm above
//     obj_init (i.e. lifted off the top); grasp_reward grasped;
//     in_place_reward in_place; obj_to_target |obj - goal|.
//   v1: reward = -|tcp - goal| in xy + (within 5 cm: max(progress(|tcp.z -
//     goal.z|), 0)), max_dist = |hand_init.z - goal.z| (maxReachDist); the
//     tcp, not the block, is rewarded; info from v1's values: obj_to_target
//     |obj_init - goal| for the whole episode (so success never changes),
//     near_object 1, grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_HOLE_HAND_INSERT_H_
#define MANYWORLDS_MANIPULATION_HOLE_HAND_INSERT_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

class HandInsert : public SawyerTask {
 public:
  explicit HandInsert(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
  void PlaceObjects(mjModel* m, mjData* d) override;

 private:
  int obj_qpos_ = -1;  // the block's free joint
};

// Grasps the block, carries it 3 cm above the top to over the goal and
// lowers it into the hole.
class HandInsertScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_HOLE_HAND_INSERT_H_
