// faucet-open, faucet-close: turn a faucet's handle to the right or to the
// left (Meta-World v3, reward version "v2").
//   faucet obj_pos in (-0.05, 0.8, 0)-(0.05, 0.85, 0) (open) or
//     (-0.1, 0.8, 0)-(0.1, 0.85, 0) (close); the handle turns about z at
//     obj_pos + (0, 0, 0.124), its 0.175 m arm pointing at the robot at
//     reset (assets/faucet_fixture.xml); goal = obj_pos + (+-0.175, 0,
//     0.125), + for open, - for close; hand starts at (0, 0.4, 0.2), bounds
//     (-0.5, 0.4, -0.15)-(0.5, 1, 0.5), which also bound the goal in the
//     observation (all as v3)
//   object point (obs[4:7]): 1 cm below the arm's end and 1.5 cm to its
//     trailing side, v3's handleStartOpen / handleStartClose site - 1 cm;
//     obs[7:11] the base's (w, x, y, z) = (1, 0, 0, 0), as v3's faucetBase
//   p = obs[4:7] + (-0.04, 0, 0.03) (open; v3 shifts it) or obs[4:7] (close)
//   in_place = tol(|p - goal|, (0, 0.07), margin | |obj_init - goal| - 0.07 |)
//   reach = gaussian(|p - tcp|, (0, 0.01), margin | |obj_init - tcp_init| - 0.01 |)
//   reward = 2 (2 reach + 3 in_place), 10 when |p - goal| <= 0.07
//   info: success |p - goal| <= 0.07 (the handle turned 1.38 rad open, 1.27
//     rad closed, as in v3); near_object |p - tcp| <= 0.01; grasp_success 1;
//     grasp_reward reach; in_place_reward in_place; obj_to_target |p - goal|.
//   (tol: long-tail tolerance; obj_init = obj_pos, v3's obj_init_pos.)
//   v1 (both): reward = -|tcp - obj| + max(progress(|obj - goal|), 0) within
//     5 cm, max_dist = |goal - obj_init| (maxPullDist); info from v1's
//     zeros: success <= 0.07, near_object 1, grasp_success 1.
#ifndef MANYWORLDS_MANIPULATION_ROTARY_FAUCET_H_
#define MANYWORLDS_MANIPULATION_ROTARY_FAUCET_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

// The two tasks differ only in the side the handle turns to: kSide = +1
// (open, right) or -1 (close, left).
template <int kSide>
class Faucet : public ArticulatedTask {
 public:
  explicit Faucet(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
  void InitTaskState(SawyerState& state) const override;
};
extern template class Faucet<1>;
extern template class Faucet<-1>;
using FaucetOpen = Faucet<1>;
using FaucetClose = Faucet<-1>;

// Pushes the handle's grip round from its trailing side with the closed
// gripper; the turning direction is read from the goal (right of the axis:
// open). Serves both tasks.
class FaucetScriptedPolicy : public Policy {
 public:
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_ROTARY_FAUCET_H_
