// Meta-World's v1 rewards (reward_function_version "v1", which Meta-World+
// restored): the pieces they share. v1 rewards are sums of a negative reach
// distance and large shaped bonuses (hundreds to thousands), not bounded in
// [0, 10] like v2's. In v1, v3's compute_reward returns zeros for most of the
// values its info fields are built from; each task's ComputeRewardV1 builds
// the info from those values exactly as its evaluate_state does.
#ifndef MANYWORLDS_MANIPULATION_REWARD_V1_H_
#define MANYWORLDS_MANIPULATION_REWARD_V1_H_

#include <limits>

#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation::v1 {

// The progress bonus every v1 reward uses for a distance d and the task's
// normaliser max_dist: 1000 (max_dist - d) + 1000 (exp(-d^2 / 0.01) +
// exp(-d^2 / 0.001)), without clamping (callers clamp where v3 does).
double Progress(double max_dist, double d);

// -reach_dist, plus, once reach_dist < 0.05, Progress(max_dist, d) (clamped
// at 0 where `clamp`): the v1 reward of the push, pull, press and turn tasks.
double ReachThenProgress(double reach_dist, double max_dist, double d, bool clamp = true);

// v1's reach term toward `point`: -|point - tcp| within xy_radius of it in
// the plane, else -(planar distance) - z_weight |tcp z - tcp z at reset|
// (v3 goes xy-first); within grip_radius, -|point - tcp| + max(a[3], 0) / 50
// (the finger-closing incentive).
double Reach(const SawyerState& s, const Vec3& point, double gripper_action, double xy_radius,
             double z_weight, double grip_radius);
// xy_radius for the rewards whose reach is the plain distance (no xy-first).
inline constexpr double kNoXyFirst = std::numeric_limits<double>::infinity();

// The object counts as dropped: below its start height + 5 mm, more than
// 2 cm from the goal and from the tcp.
bool Dropped(const SawyerState& s, double obj_z, double place_dist, double reach_dist);

// The lift bonus: 100 (height target - floor) while `held`, else
// 100 (min(height target, obj_z) - floor) while `near` and the object is
// 5 mm above its start height, else 0. floor: 0 except where v3 counts the
// lift from elsewhere.
double LiftBonus(const SawyerState& s, double obj_z, bool held, bool near, double floor = 0.0);

// The pick-and-place v1 reward (pick-place, and the tasks that copy it):
// reach (with v3's xy-first shaping and the finger-closing incentive), a lift
// bonus once the object is at the lift target, and a place bonus toward
// the goal while lifted and not dropped. `place_dist` is |obj - goal| (the
// drop test reads it); `progress_dist` the distance the place bonus reads
// (the same in pick-place; the peg's head in peg-insert-side until it is
// within 5 cm). z_weight: the weight of
// the tcp's height change in the xy-first reach (2 in pick-place, 1 in
// peg-insert-side).
// lift_from_start: the lift bonus counts the height above the object's start
// plus 2 cm (pick-out-of-hole), not the height above the table.
double PickPlace(const SawyerState& s, double gripper_action, double place_dist,
                 double progress_dist, double z_weight, bool lift_from_start = false);

// The whole v1 step of pick-place and the tasks that copy it (|obj - goal|
// for both distances, the tcp's height change weighted 2): the reward, and
// the info v3's evaluate_state builds from v1's (reward, 0, 0, |obj - goal|,
// 0, 0): success within success_radius, near_object 1, obj_to_target.
RewardTerms PickPlaceStep(const SawyerState& s, double gripper_action, double success_radius,
                          bool lift_from_start = false);

// The lift target and normaliser v3 sets at reset for pick-and-place:
// obj_height = the object's height, height_target = obj_height + lift,
// max_dist = |(obj_init.xy, height_target) - goal| + height_target.
void InitPickPlace(SawyerState& s, double obj_height, double lift);

// The reward and info v3's evaluate_state builds from v1's (reward, 0, 0,
// obj_to_target, 0, 0): success within success_radius, near_object 1,
// grasp_success as given (0 in most tasks).
RewardTerms StepTerms(double reward, double obj_to_target, double success_radius,
                      double grasp_success = 0.0);

// The v1 step of the push, pull, press and turn tasks: ReachThenProgress
// (reach_dist, s.v1_max_dist, dist, clamp), and the info v3's evaluate_state
// builds from v1's (reward, 0, 0, dist, 0, 0): success within
// success_radius, near_object 1, grasp_success as given, obj_to_target dist.
RewardTerms ReachThenProgressStep(const SawyerState& s, double reach_dist, double dist,
                                  double success_radius, double grasp_success = 0.0,
                                  bool clamp = true);

// The v1 step of the push tasks (push, push-back, push-wall, soccer):
// ReachThenProgress from the tcp-object distance and the object's distance
// to the goal in xy, and the info v3's evaluate_state builds from v1's
// (reward, 0, 0, push_dist, 0, 0): success within success_radius,
// near_object 1, obj_to_target.
RewardTerms PushStep(const SawyerState& s, double success_radius);
// max_dist = |obj_init - goal| in xy (maxPushDist), as v3 sets it at reset.
void InitPush(SawyerState& s);

}  // namespace manyworlds::manipulation::v1

#endif  // MANYWORLDS_MANIPULATION_REWARD_V1_H_
