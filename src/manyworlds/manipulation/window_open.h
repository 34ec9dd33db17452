// window-open: slide a window sash open (+x) by its handle until the handle
// is within 0.05 m of the goal (metaworld.md §2.9).
//   obj_pos = the handle with the sash shut, in [(-0.1, 0.7, 0.16),
//     (0.1, 0.9, 0.16)]; goal = the handle slid 0.2 m = obj_pos + (0.2, 0, 0);
//     hand starts at (0, 0.4, 0.2)
//   reward (MoveHandleReward in articulated.h, radius 0.05):
//     reach = tol(d, (0, 0.02), margin |tcp_init - handle_init|), d = the
//       distance from the handle to the nearest of tcp and pads
//     in_place = tol(|handle - goal|, (0, 0.05), margin |handle_init - goal|)
//     reward = 2 reach + 8 in_place; 10 on success
//   info: success |handle - goal| <= 0.05; near_object d <= 0.03;
//     grasp_success = a pad touches the handle; grasp_reward = reach;
//     in_place_reward; obj_to_target = |handle - goal|.
#ifndef MANYWORLDS_MANIPULATION_WINDOW_OPEN_H_
#define MANYWORLDS_MANIPULATION_WINDOW_OPEN_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class WindowOpen : public ArticulatedTask {
 public:
  explicit WindowOpen(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Pushes the handle bar to the goal with one open finger pad
// (PushBarAlongX).
class WindowOpenScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_WINDOW_OPEN_H_
