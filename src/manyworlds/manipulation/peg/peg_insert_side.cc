#include "manyworlds/manipulation/peg/peg_insert_side.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kHalfLength = 0.1;  // peg centre to head
// Meta-World v3: the goal is box + (0.03, 0, 0.13), 6.6 cm inside the box's
// front face (x = +0.096 from the box); success weights y and z twice.
constexpr Vec3 kGoalOnBox{0.03, 0.0, 0.13};
constexpr double kTargetRadius = 0.07;  // success, and the in-place tolerance
constexpr double kV1Lift = 0.11;  // v3's liftThresh
constexpr Vec3 kYzTwice{1.0, 2.0, 2.0};
constexpr double kHoleClearance = 0.01;  // per side, around the peg
constexpr double kMouthToGoal = 0.066;   // front face to goal, in x
// The policy lines the head up this far in front of the goal before
// pushing in.
constexpr double kPreInsert = 0.12;
// v3's observed object point ("pegGrasp"), in the peg's frame.
constexpr Vec3 kGraspPoint{0.03, 0.0, 0.01};
// v3 reads the head's "initial" position before it moves the peg to the
// variation, so its in-place margin starts from the peg's default pose,
// this point, in every variation. We use the same point.
constexpr Vec3 kV3HeadInit{-0.1, 0.6, 0.0147847};
// v3's two prisms in front of the face, below and above the hole, relative
// to the goal (corner "zero", corner "one"): a head inside them loses
// in-place reward.
constexpr Vec3 kBelowZero{0.0800796, 0.0999124, -0.12}, kBelowOne{0.1199203, -0.1001194, -0.034};
constexpr Vec3 kAboveZero{0.0800796, 0.0999124, 0.03}, kAboveOne{0.1399203, -0.1001353, 0.06};

Vec3 Plus(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }

// The peg frame's point `local` given the frame's origin and (x, y, z, w)
// quaternion.
Vec3 PegPoint(const Vec3& origin, const float* q, const Vec3& local) {
  const double qx = q[0], qy = q[1], qz = q[2], qw = q[3];
  const double r[3][3] = {{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)},
                          {2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx)},
                          {2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)}};
  Vec3 p = origin;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p[i] += r[i][j] * local[j];
  }
  return p;
}

}  // namespace

SawyerTaskConfig PegInsertSide::Config() {
  // v3 draws the box in (-0.35, 0.4, 0)-(-0.25, 0.7, 0); the goal is
  // kGoalOnBox from it. Its 0.1 m peg-box rule never binds (x gap >= 0.25).
  SawyerTaskConfig config = TaskConfig(
      "peg-insert-side", "Sawyer arm: insert a peg into the hole in the side of a box",
      "peg_insert_side.xml", {{0.0, 0.5, 0.02}, {0.2, 0.7, 0.02}},
      {{-0.35 + kGoalOnBox[0], 0.4, kGoalOnBox[2]}, {-0.25 + kGoalOnBox[0], 0.7, kGoalOnBox[2]}});
  config.min_obj_goal_xy = 0.0;
  // v3's goal_space: the goals' box with z widened 1 mm either way (v3 draws
  // the box's height in (-0.001, 0.001); ours stands on the table).
  config.goal_space = Range3{{-0.32, 0.4, 0.129}, {-0.22, 0.7, 0.131}};
  return config;
}

PegInsertSide::PegInsertSide(SawyerOptions options)
    : GoalFixtureTask(Config(), "box", kGoalOnBox, options) {
  const sim::IdLookup ids(model(), config().xml_file);
  peg_head_ = ids.Site("peg_head");
  peg_grasp_ = ids.Site("obj_point");
}

void PegInsertSide::RefreshTaskState(const mjData* d, SawyerState& state) const {
  state.obj = SitePosition(d, peg_grasp_);
  state.obj_head = SitePosition(d, peg_head_);
  state.obj_head_init = kV3HeadInit;
}

RewardTerms PegInsertSide::ComputeReward(const SawyerState& s,
                                         std::span<const float> action) const {
  const double obj_to_target = WeightedDistance(s.obj_head, s.goal, kYzTwice);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double to_goal = LongTailTolerance(obj_to_target, 0.0, kTargetRadius,
                                           WeightedDistance(s.obj_head_init, s.goal, kYzTwice));
  const double walls =
      HamacherProduct(RectPrismTolerance(s.obj_head, Plus(s.goal, kAboveZero), Plus(s.goal, kAboveOne)),
                      RectPrismTolerance(s.obj_head, Plus(s.goal, kBelowZero), Plus(s.goal, kBelowOne)));
  const double in_place = HamacherProduct(to_goal, walls);

  const CagingParams caging{.obj_radius = 0.0075, .pad_success_thresh = 0.03, .high_density = true};
  const bool held = HeldAndLifted(s, 0.08, 0.01);
  const double grasped = held ? 1.0 : CageObject(s, s.obj, action[3], caging);

  RewardTerms terms;
  terms.reward = HamacherProduct(grasped, in_place);
  if (held) terms.reward += 1.0 + 5.0 * in_place;
  terms.success = obj_to_target <= kTargetRadius;
  if (terms.success) terms.reward = 10.0;
  terms.near_object = tcp_to_obj <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = HeldAndLifted(s, 0.02, 0.01) ? 1.0 : 0.0;
  terms.grasp_reward = grasped;
  terms.in_place_reward = in_place;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void PegInsertSide::InitTaskState(SawyerState& s) const {
  v1::InitPickPlace(s, s.obj_init[2], kV1Lift);
}

RewardTerms PegInsertSide::ComputeRewardV1(const SawyerState& s,
                                           std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double head_to_target = Distance(s.obj_head, s.goal);
  // v3 rewards the head's distance until it is within 5 cm, then the peg's
  const double progress_dist = head_to_target <= 0.05 ? obj_to_target : head_to_target;
  return v1::StepTerms(v1::PickPlace(s, action[3], obj_to_target, progress_dist, 1.0),
                       obj_to_target, kTargetRadius);
}

void PegInsertSideScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                      std::span<float> action) {
  const SawyerObs o(env_obs);
  // The observed point is the grasp point; the head is found from it and
  // the peg's (x, y, z, w) quaternion.
  const Vec3 head = PegPoint(o.obj1, env_obs.data() + kObsObj1Quat,
                             {-kHalfLength - kGraspPoint[0], -kGraspPoint[1], -kGraspPoint[2]});

  const Vec3& goal = o.goal;
  const double off_axis = std::hypot(head[1] - goal[1], head[2] - goal[2]);
  // Line up in front of the mouth first; once in line (or already in the
  // hole) drive the head to the goal.
  const bool outside = head[0] > goal[0] + kMouthToGoal + 0.015;
  const Vec3 head_to = outside && off_axis > kHoleClearance / 2
                           ? Vec3{goal[0] + kPreInsert, goal[1], goal[2]}
                           : goal;
  // While held the peg moves with the tcp, so shift the tcp by the head's
  // error.
  Vec3 carry_to;
  for (int i = 0; i < 3; ++i) carry_to[i] = o.tcp[i] + head_to[i] - head[i];
  GraspAndCarry(o, carry_to, action);
}

}  // namespace manyworlds::manipulation
