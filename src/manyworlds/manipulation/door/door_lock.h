// door-lock, door-unlock: turn the bar of a lock on a shut door down to lock
// it, or up to unlock it (Meta-World v3, reward version "v2").
//   door obj_pos in (-0.1, 0.8, 0.15)-(0.1, 0.85, 0.15), door-open's door
//     (door_fixture.h's geometry) without its hinge; the bar turns about an axis along
//     y at lock = obj_pos + (0, -0.118, 0.061) (v3's lock_link, its
//     obj_init_pos), from 0 (pointing +x) to 1.57 rad (pointing down)
//     (assets/door_lock.xml); door-lock starts at 0, door-unlock at pi/2;
//     hand starts at (0, 0.6, 0.2), bounds (-0.5, 0.4, -0.15)-(0.5, 1, 0.5)
//   object point (obs[4:7]): 0.09 m along the bar, 0.04 m in front of the
//     axis and 1 cm to one side of it (v3's lockStartLock / lockStartUnlock
//     sites); obs[7:11] the door's (w, x, y, z) = (1, 0, 0, 0) (v3's door_link)
//   goal bounds in the observation: v3's goal_space, the hand's bounds
//     (door-lock), (0, 0.64, 0.21)-(0.2, 0.7, 0.2111) (door-unlock), wider
//     than where the goals lie
//   door-lock: goal = lock + (0, -0.04, -0.1);
//     d = |(obj - left_pad) * (0.25, 1, 0.5)|; near = tol(d, (0, 0.01),
//     margin d) (v3's margin reads its init_left_pad, a view of the live pad);
//     obj_to_target = |goal z - obj z|;
//     pressed = tol(obj_to_target, (0, 0.005), margin 0.1);
//     reward = 2 H(max(obs[3], 0), near) + 8 pressed
//     info: near_object d <= 0.05; grasp_reward near
//   door-unlock: goal = lock + (0.1, -0.04, 0);
//     d = |(hand + (0, 0.055, 0.07) - obj) * (0.25, 1, 0.5)| (hand = obs[0:3]);
//     ready = tol(d, (0, 0.02), margin |(tcp_init + (0, 0.055, 0.07) - lock) *
//     (0.25, 1, 0.5)|); obj_to_target = |goal x - obj x|;
//     pushed = tol(obj_to_target, (0, 0.005), margin 0.1);
//     reward = 2 ready + 8 pushed
//     info: near_object d <= 0.05; grasp_reward ready
//   both: success obj_to_target <= 0.02 (locked: the bar turned past 1.21 rad;
//     unlocked: back to 0.35 rad, as in v3); grasp_success obs[3] > 0;
//     in_place_reward pressed / pushed; obj_to_target as above.
//   (tol: long-tail tolerance; H: Hamacher product. The record's obj_init is
//   the lock's axis point, v3's obj_init_pos.)
#ifndef MANYWORLDS_MANIPULATION_DOOR_DOOR_LOCK_H_
#define MANYWORLDS_MANIPULATION_DOOR_DOOR_LOCK_H_

#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/articulated.h"

namespace manyworlds::manipulation {

// The lock on the shut door, shared by both tasks.
class DoorLockTask : public ArticulatedTask {
 protected:
  DoorLockTask(SawyerTaskConfig config, FixtureSpec fixture, SawyerOptions options);
  // obj_init = the lock's axis point.
  void InitTaskState(SawyerState& state) const override;
  // v1 (both tasks): -|tcp - obj| + max(progress(|obj - goal|), 0) within
  // 5 cm, max_dist = |goal - obj_init| (maxPullDist); info from v1's zeros:
  // success <= 0.02, near_object 1, grasp_success 0.
  RewardTerms ComputeRewardV1(const SawyerState& state,
                              std::span<const float> action) const override;
};

class DoorLock : public DoorLockTask {
 public:
  explicit DoorLock(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

class DoorUnlock : public DoorLockTask {
 public:
  explicit DoorUnlock(SawyerOptions options = {});
  static SawyerTaskConfig Config();

 protected:
  RewardTerms ComputeReward(const SawyerState& state, std::span<const float> action) const override;
};

// Pushes the bar down from above (lock) or up from its -x side (unlock)
// with the closed gripper, coming in from in front of the door.
class DoorLockScriptedPolicy : public Policy {
 public:
  explicit DoorLockScriptedPolicy(bool unlock = false) : unlock_(unlock) {}
  void Act(std::span<const float> env_obs, std::span<const float> task_obs,
           std::span<float> action) override;

 private:
  bool unlock_;
};
struct DoorUnlockScriptedPolicy : DoorLockScriptedPolicy {
  DoorUnlockScriptedPolicy() : DoorLockScriptedPolicy(/*unlock=*/true) {}
};

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_MANIPULATION_DOOR_DOOR_LOCK_H_
