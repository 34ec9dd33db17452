// reach and reach-wall: bring the gripper's tcp within 5 cm of a goal in
// space; the puck is a distractor. One class: ReachVariant::kWall puts a
// wall between the start and the goal (wall.h) and leaves three info values
// 0, as v3's reach-wall does.
//   reach: object in [(-0.1, 0.6, 0.02), (0.1, 0.7, 0.02)], goal in
//     [(-0.1, 0.8, 0.05), (0.1, 0.9, 0.3)], >= 0.15 m from it in xy
//   reach-wall: goal in (-0.05, 0.85, 0.05)-(0.05, 0.9, 0.3) (wall.h)
//   reward = 10 tol(|tcp - goal|, (0, 0.05), margin |hand_init - goal|)
//   info: success |tcp - goal| <= 0.05; obj_to_target = |tcp - goal|;
//     in_place_reward = the tolerance term; reach: near_object and
//     grasp_reward = |tcp - goal|, grasp_success = 1; reach-wall: those 0.
//   v1: reward = max(progress(|tcp - goal|), 0) with max_dist = |tcp_init -
//     goal| (maxReachDist); info as above with in_place_reward 0.
#ifndef MANYWORLDS_MANIPULATION_REACH_REACH_H_
#define MANYWORLDS_MANIPULATION_REACH_REACH_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {

enum class ReachVariant { kOpen, kWall };

class Reach : public SawyerTask {
 public:
  explicit Reach(ReachVariant variant = ReachVariant::kOpen, SawyerOptions options = {});
  static SawyerTaskConfig Config(ReachVariant variant = ReachVariant::kOpen);

 protected:
  RewardTerms ComputeReward(const SawyerState& state,
                            std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;

 private:
  // The info both reward versions give at this distance.
  RewardTerms Info(double tcp_to_goal) const;

  ReachVariant variant_;
};

// Moves the tcp straight to the observed goal (needs an observable goal);
// with the wall, above it until past it.
class ReachScriptedPolicy : public Policy {
 public:
  explicit ReachScriptedPolicy(ReachVariant variant = ReachVariant::kOpen) : variant_(variant) {}
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;

 private:
  ReachVariant variant_;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_REACH_REACH_H_
