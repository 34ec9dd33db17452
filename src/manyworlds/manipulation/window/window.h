// window-open and window-close: slide a window sash by its handle until the
// object point is within 0.05 m of the goal in x (Meta-World v3, reward
// version "v2"). One class; the direction (WindowMotion) picks the ranges,
// the sash's start and two reward terms.
//   window-open: window obj_pos in [(-0.1, 0.7, 0.16), (0.1, 0.9, 0.16)]
//     (v3's window body); the handle bar is at obj_pos + (-0.014, -0.095, 0)
//     with the sash shut and the object point (obs[4:7]) 2.6 cm to its -x
//     side, at obj_pos + (-0.04, -0.095, 0); goal = obj_pos + (0.2, 0, 0),
//     so success needs the sash slid >= 0.19 m of its 0.2 m (+x).
//   window-close: window obj_pos in [(0, 0.75, 0.2), (0, 0.9, 0.2)]; the
//     handle bar is at obj_pos + (-0.014, -0.095, 0) with the sash shut and
//     the object point 2.4 cm to its +x side; the sash starts slid open
//     0.2 m; goal = obj_pos, so success needs the sash within 0.04 m of
//     shut (-x).
//   Both: hand starts at (0, 0.4, 0.2); obs[7:11] zeros (as v3).
//   in_place = tol(|handle_x - goal_x|, (0, 0.05),
//     margin ||start_x - goal_x| - 0.05|) (start: obj_init = obj_pos in
//     window-open, handle_init in window-close)
//   reach = tol(|handle - tcp|, (0, 0.02),
//     margin ||handle_init - tcp_init| - 0.02|) (window-close: tolG)
//   reward = 10 H(reach, in_place) (no success bonus)
//   info: success |handle_x - goal_x| <= 0.05; near_object |handle - tcp|
//     <= 0.05; grasp_success 1 (as v3); grasp_reward = reach;
//     in_place_reward = in_place; obj_to_target = |handle_x - goal_x|.
//   (tol: long-tail, tolG: gaussian tolerance; H: Hamacher product.)
//   v1: reward = -|tcp - obj| + (|tcp - obj| < 0.05 ? progress(|obj.x -
//     goal.x|) : 0) (not clamped, as v3), max_dist 0.2 (maxPullDist); info
//     from v1's zeros: success |obj.x - goal.x| <= 0.05, near_object 1,
//     grasp_success 1.
#ifndef MANYWORLDS_MANIPULATION_WINDOW_WINDOW_H_
#define MANYWORLDS_MANIPULATION_WINDOW_WINDOW_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

enum class WindowMotion { kOpen, kClose };

class Window : public ArticulatedTask {
 public:
  explicit Window(WindowMotion motion, SawyerOptions options = {});
  static SawyerTaskConfig Config(WindowMotion motion);

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;

 private:
  WindowMotion motion_;
};

// Pushes the handle bar to the goal with one open finger pad
// (PushBarAlongX): to the stop (open) or the shut position (close).
class WindowScriptedPolicy : public Policy {
 public:
  explicit WindowScriptedPolicy(WindowMotion motion) : motion_(motion) {}
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;

 private:
  WindowMotion motion_;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_WINDOW_WINDOW_H_
