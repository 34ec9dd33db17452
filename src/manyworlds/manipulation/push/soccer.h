// soccer (Meta-World v3): push the ball into the goal net.
//   ball in (-0.1, 0.6)-(0.1, 0.7); goal (the net) in (-0.1, 0.8, 0)-
//   (0.1, 0.9, 0), >= 0.15 m from the ball in xy
//   reward (v3): d = |(ball - goal) (3, 1, 1)|; in_place = tol(d, (0, 0.07),
//     margin |(ball - ball_init) (3, 1, 1)|) (v3's margin is the distance
//     the ball has moved from its start, so in_place is 0 until it moves);
//     past the goal line (goal y - 0.1) more than 10 cm to the side of the
//     goal, in_place falls by 2 (y - line) / (1 - line); g = sweep-style
//     caging (radius 0.013, grip band 1 cm, xz 0.005); 3 g + 6.5 in_place;
//     10 with d < 0.07.
//   info: success |ball - goal| <= 0.07 (unweighted, as v3 computes it);
//     obj_to_target |ball - goal|.
//   v1: reward = -|tcp - obj| + max(progress(xy distance to the goal), 0)
//     within 5 cm, max_dist = |obj_init - goal| in xy (maxPushDist); info
//     from v1's zeros: success xy distance <= 0.07, near_object 1,
//     grasp_success 0.
#ifndef MANYWORLDS_MANIPULATION_PUSH_SOCCER_H_
#define MANYWORLDS_MANIPULATION_PUSH_SOCCER_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/object_tasks.h"

namespace manyworlds::manipulation {

class Soccer : public GoalFixtureTask {
 public:
  explicit Soccer(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};

// Pushes the ball into the net with the closed fingers.
class SoccerScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_PUSH_SOCCER_H_
