// window-close: slide an open window sash shut (-x) by its handle until the
// handle is within 0.05 m of its shut position (metaworld.md §2.9).
//   obj_pos = the handle with the sash shut, in [(0, 0.75, 0.2),
//     (0, 0.9, 0.2)]; the sash starts slid open 0.2 m; goal = obj_pos;
//     hand starts at (0, 0.4, 0.2)
//   reward (MoveHandleReward in articulated.h, radius 0.05):
//     reach = tol(d, (0, 0.02), margin |tcp_init - handle_init|), d = the
//       distance from the handle to the nearest of tcp and pads
//     in_place = tol(|handle - goal|, (0, 0.05), margin |handle_init - goal|)
//     reward = 2 reach + 8 in_place; 10 on success
//   info: success |handle - goal| <= 0.05; near_object d <= 0.03;
//     grasp_success = a pad touches the handle; grasp_reward = reach;
//     in_place_reward; obj_to_target = |handle - goal|.
#ifndef MANYWORLDS_MANIPULATION_WINDOW_CLOSE_H_
#define MANYWORLDS_MANIPULATION_WINDOW_CLOSE_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

class WindowClose : public ArticulatedTask {
 public:
  explicit WindowClose(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Pushes the handle bar to the goal with one open finger pad
// (PushBarAlongX).
class WindowCloseScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_WINDOW_CLOSE_H_
