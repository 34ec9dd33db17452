#include "manyworlds/manipulation/peg_insert_side.h"

#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kHalfLength = 0.1;   // peg centre to head
constexpr double kHoleHeight = 0.13;  // hole axis above the box base
constexpr double kSuccessRadius = 0.07;
constexpr double kHoleClearance = 0.01;  // per side, around the peg
constexpr double kMouthToGoal = 0.075;   // the goal's depth in the hole
// The policy lines the head up this far in front of the goal before
// pushing in.
constexpr double kPreInsert = 0.12;

}  // namespace

SawyerTaskConfig PegInsertSide::Config() {
  SawyerTaskConfig config;
  config.id = "peg-insert-side";
  config.description = "Sawyer arm: insert a peg into the hole in the side of a box";
  config.xml_file = "peg_insert_side.xml";
  config.obj_low = {0.0, 0.5, 0.02};
  config.obj_high = {0.2, 0.7, 0.02};
  config.goal_low = {-0.35, 0.4, kHoleHeight};
  config.goal_high = {-0.25, 0.7, kHoleHeight};
  return config;
}

PegInsertSide::PegInsertSide(SawyerOptions options) : SawyerTask(Config(), options) {
  const sim::IdLookup ids(model(), config().xml_file);
  peg_head_ = ids.Site("peg_head");
  box_ = ids.Body("box");
}

void PegInsertSide::PlaceObjects(mjModel* m, mjData* d) {
  SawyerTask::PlaceObjects(m, d);
  const Vec3& goal = goal_pos();
  PlaceFixture(m, box_, {goal[0], goal[1], goal[2] - kHoleHeight});
}

RewardTerms PegInsertSide::ComputeReward(const SawyerState& s,
                                         std::span<const float> action) const {
  const Vec3 head = SitePosition(data(), peg_head_);
  // The peg starts upright, so its head starts half a length toward -x.
  const Vec3 head_init{s.obj_init[0] - kHalfLength, s.obj_init[1], s.obj_init[2]};
  const double obj_to_target = Distance(head, s.goal);
  const double tcp_to_obj = Distance(s.tcp, s.obj);

  const Vec3 weights{1.0, 2.0, 2.0};
  const double to_goal = LongTailTolerance(WeightedDistance(head, s.goal, weights), 0.0, 0.05,
                                           WeightedDistance(head_init, s.goal, weights));
  const double off_axis = std::hypot(head[1] - s.goal[1], head[2] - s.goal[2]);
  const double on_axis = LongTailTolerance(off_axis, 0.0, kHoleClearance, 0.1);
  const double in_place = HamacherProduct(to_goal, on_axis);

  CagingParams caging;
  caging.obj_radius = 0.015;
  caging.pad_success_thresh = 0.05;
  caging.xz_thresh = 0.005;
  caging.high_density = true;
  const double grasped = CageObject(s, s.obj, action[3], caging);

  RewardTerms terms;
  terms.reward = HamacherProduct(grasped, in_place);
  if (HeldAndLifted(s, 0.03, 0.01)) terms.reward += 1.0 + 5.0 * in_place;
  terms.success = obj_to_target <= kSuccessRadius;
  if (terms.success) terms.reward = 10.0;
  terms.near_object = tcp_to_obj <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = GraspSuccess(s);
  terms.grasp_reward = grasped;
  terms.in_place_reward = in_place;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void PegInsertSideScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                      std::span<float> action) {
  const SawyerObs o(env_obs);
  // The peg's x axis from its (x, y, z, w) quaternion; the head is half a
  // length back along it.
  const double qx = env_obs[kObsObj1Quat], qy = env_obs[kObsObj1Quat + 1],
               qz = env_obs[kObsObj1Quat + 2], qw = env_obs[kObsObj1Quat + 3];
  const Vec3 axis{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qw * qz), 2 * (qx * qz - qw * qy)};
  Vec3 head;
  for (int i = 0; i < 3; ++i) head[i] = o.obj1[i] - kHalfLength * axis[i];

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
