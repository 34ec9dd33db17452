// Meta-World's v1 rewards (reward_function_version "v1", which Meta-World+
// restored): the pieces they share. v1 rewards are sums of a negative reach
// distance and large shaped bonuses (hundreds to thousands), not bounded in
// [0, 10] like v2's. In v1, v3's compute_reward returns zeros for most of the
// values its info fields are built from; each task's ComputeRewardV1 builds
// the info from those values exactly as its evaluate_state does.
#ifndef MANYWORLDS_MANIPULATION_REWARD_V1_H_
#define MANYWORLDS_MANIPULATION_REWARD_V1_H_

#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation::v1 {

// The progress bonus every v1 reward uses for a distance d and the task's
// normaliser max_dist: 1000 (max_dist - d) + 1000 (exp(-d^2 / 0.01) +
// exp(-d^2 / 0.001)), without clamping (callers clamp where v3 does).
double Progress(double max_dist, double d);

// -reach_dist, plus, once reach_dist < 0.05, Progress(max_dist, d) (clamped
// at 0 where `clamp`): the v1 reward of the push, pull, press and turn tasks.
double ReachThenProgress(double reach_dist, double max_dist, double d, bool clamp = true);

// The pick-and-place v1 reward (pick-place, and the tasks that copy it):
// reach (with v3's xy-first shaping and the finger-closing incentive), a lift
// bonus once the object is at the lift target, and a place bonus toward
// the goal while lifted and not dropped. `place_dist` is |obj - goal| (the
// drop test reads it); `progress_dist` the distance the place bonus reads
// (the same in pick-place; the peg's head in peg-insert-side until it is
// within 5 cm). z_weight: the weight of
// the tcp's height change in the xy-first reach (2 in pick-place, 1 in
// peg-insert-side).
struct PickPlaceTerms {
  double reward = 0;
  double reach_dist = 0;  // |obj - tcp|
  double place_dist = 0;  // |obj - goal|
};
// lift_from_start: the lift bonus counts the height above the object's start
// plus 2 cm (pick-out-of-hole), not the height above the table.
PickPlaceTerms PickPlace(const SawyerState& s, double gripper_action, double place_dist,
                         double progress_dist, double z_weight, bool lift_from_start = false);

// The lift target and normaliser v3 sets at reset for pick-and-place:
// obj_height = the object's height, height_target = obj_height + lift,
// max_dist = |(obj_init.xy, height_target) - goal| + height_target.
void InitPickPlace(SawyerState& s, double obj_height, double lift);

}  // namespace manyworlds::manipulation::v1

#endif  // MANYWORLDS_MANIPULATION_REWARD_V1_H_
