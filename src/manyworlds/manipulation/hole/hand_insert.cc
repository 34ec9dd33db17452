#include "manyworlds/manipulation/hole/hand_insert.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kTargetRadius = 0.05;
// The block's centre resting on the top is this far above v3's obj_pos.
constexpr double kRestAboveObjPos = 0.02;

}  // namespace

SawyerTaskConfig HandInsert::Config() {
  SawyerTaskConfig config = TaskConfig(
      "hand-insert", "Sawyer arm: push a block over the table into a hole", "hand_insert.xml",
      {{-0.1, 0.6, 0.05}, {0.1, 0.7, 0.05}}, {{-0.04, 0.8, -0.0201}, {0.04, 0.88, -0.0199}});
  config.hand_low = {-0.5, 0.40, -0.15};
  config.obj_quat = QuatLayout::kWxyz;
  return config;
}

HandInsert::HandInsert(SawyerOptions options) : SawyerTask(Config(), options) {
  const mjModel* m = model();
  obj_qpos_ = m->jnt_qposadr[m->body_jntadr[mj_name2id(m, mjOBJ_BODY, "obj")]];
}

void HandInsert::PlaceObjects(mjModel* m, mjData* d) {
  SawyerTask::PlaceObjects(m, d);
  d->qpos[obj_qpos_ + 2] += kRestAboveObjPos;
}

RewardTerms HandInsert::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.obj, s.tcp);
  const double in_place = TowardGoal(s, obj_to_target, kTargetRadius);
  const double grasped = CageObject(s, s.obj, action[3], {.high_density = true});

  double reward = HamacherProduct(grasped, in_place);
  if (tcp_to_obj < 0.02 && s.gripper_opening > 0) reward += 1.0 + 7.0 * in_place;
  return ObjectRewardTerms(s, {.reward = reward, .at_target = obj_to_target < kTargetRadius,
                               .obj_to_target = obj_to_target, .success_radius = kTargetRadius,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = in_place});
}

void HandInsert::InitTaskState(SawyerState& s) const {
  s.v1_max_dist = std::abs(s.hand_init[2] - s.goal[2]);  // v3's maxReachDist
}

RewardTerms HandInsert::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double reach_xy = std::hypot(s.tcp[0] - s.goal[0], s.tcp[1] - s.goal[1]);
  const double reach_z = std::abs(s.tcp[2] - s.goal[2]);
  const double near = reach_xy < 0.05 ? v1::Progress(s.v1_max_dist, reach_z) : 0.0;
  // v3's evaluate_state on v1's (reward, 0, 0, |obj_init - goal|, 0, 0): the
  // distance (and so success) never changes during an episode
  const double obj_to_target = Distance(s.obj_init, s.goal);
  return v1::StepTerms(-reach_xy + std::max(near, 0.0), obj_to_target, kTargetRadius);
}

void HandInsertScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  // Carried with its bottom 3 cm above the top (centre 0.1), then down onto
  // the hole floor (centre 0.02).
  GraspAndCarryOver(o, {o.goal[0], o.goal[1], 0.02}, 0.1, 0.01, action);
}

}  // namespace manyworlds::manipulation
