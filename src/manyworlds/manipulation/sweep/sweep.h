// sweep and sweep-into: slide the puck along the table, gripped, to a goal:
// sideways into the goal zone at the table's +x edge (sweep), or across
// into a pocket (sweep-into: three low walls around the goal, open toward
// the robot). One class; SweepVariant picks the goal, the caging's bands
// and two details of the rewards.
//   puck in [(-0.1, 0.6, 0.02), (0.1, 0.7, 0.02)]
//   sweep: goal (0.5, obj_y, 0.01), the table's edge on the puck's row (v3
//     samples none; its range [(0.49, 0.6, 0), (0.51, 0.7, 0.02)] only
//     bounds the observation); obs[7:11] the puck's (w, x, y, z), as v3's
//   sweep-into: goal fixed at (0, 0.84, 0.02), >= 0.15 m from the puck in
//     xy; the pocket's mouth is at y = 0.785, so success means the puck is
//     in it. Distances to the goal are measured at the puck's height. The
//     observation bounds the goal by v3's goal_space, (+-0.001, 0.84 +-
//     0.0001, 0.02 +- 0.0001); obs[7:11] (x, y, z, w), as v3's.
//   in_place = tol(|obj - goal|, (0, 0.05), margin |obj_init - goal|)
//   grasped = SweepCaging (object_tasks.h): pads within 1 cm past the
//     puck's 2 cm radius, tcp within 5 mm in xz (sweep-into: 5 mm, 1 cm)
//   reward = 2 grasped + 6 H(grasped, in_place); 10 once |obj - goal| < 0.05
//   info: success |obj - goal| <= 0.05; near_object |tcp - obj| <= 0.03;
//     grasp_success = a pad touches the puck and opening > 0;
//     grasp_reward = grasped; in_place_reward; obj_to_target = |obj - goal|.
//   v1: reward = -|tcp - obj| + max(progress(xy distance to the goal), 0)
//     within 5 cm, both terms' distances 0 once the puck is 5 cm below its
//     start (sweep-into: with 0.4 < y < 1), max_dist = |obj_init - goal| in
//     xy (maxPushDist); info from v1's zeros: success distance <= 0.05,
//     near_object 1.
#ifndef MANYWORLDS_MANIPULATION_SWEEP_SWEEP_H_
#define MANYWORLDS_MANIPULATION_SWEEP_SWEEP_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

enum class SweepVariant { kEdge, kInto };

class Sweep : public SawyerTask {
 public:
  explicit Sweep(SweepVariant variant = SweepVariant::kEdge, SawyerOptions options = {});
  static SawyerTaskConfig Config(SweepVariant variant = SweepVariant::kEdge);

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
  Vec3 DeriveGoal(const Vec3& obj, const Vec3& drawn_goal) const override;

 private:
  SweepVariant variant_;
};

// Closes on the puck and slides it, 5 mm above the table, to the goal.
class SweepScriptedPolicy : public Policy {
 public:
  explicit SweepScriptedPolicy(SweepVariant variant = SweepVariant::kEdge) : variant_(variant) {}
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;

 private:
  SweepVariant variant_;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_SWEEP_SWEEP_H_
