#include "manyworlds/manipulation/container/box_close.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"

namespace manyworlds::manipulation {
namespace {

// The lid frame at rest on the table (its rims 1.6 cm tall).
constexpr double kLidRestZ = 0.016;
// Upright: turned 90 degrees about z, (w, x, y, z) as v3 writes it.
constexpr double kUprightQuat[4] = {0.707, 0.0, 0.0, 0.707};
// The handle's centre above the lid frame.
constexpr double kHandleAboveLid = 0.033;
// v1: v3's objHeight (its handle's height at reset, before its lid settles
// into the rest pose ours starts in) and liftThresh.
constexpr double kV1ObjHeight = 0.14732;
constexpr double kV1Lift = 0.12;

double QuatReward(const std::array<double, 4>& q) {
  double sum = 0;
  for (int i = 0; i < 4; ++i) sum += (q[i] - kUprightQuat[i]) * (q[i] - kUprightQuat[i]);
  return std::max(1.0 - std::sqrt(sum) / 0.2, 0.0);
}

}  // namespace

SawyerTaskConfig BoxClose::Config() {
  SawyerTaskConfig config =
      TaskConfig("box-close", "Sawyer arm: put the lid on the box", "box_close.xml",
                 {{-0.05, 0.5, 0.02}, {0.05, 0.55, 0.02}}, {{-0.1, 0.7, 0.133}, {0.1, 0.8, 0.133}});
  config.min_obj_goal_xy = 0.25;
  config.obj_quat = QuatLayout::kWxyz;
  return config;
}

BoxClose::BoxClose(SawyerOptions options) : SawyerTask(Config(), options) {
  const mjModel* m = model();
  box_ = mj_name2id(m, mjOBJ_BODY, "box");
  lid_qpos_ = m->jnt_qposadr[m->body_jntadr[mj_name2id(m, mjOBJ_BODY, "obj")]];
}

void BoxClose::PlaceObjects(mjModel* m, mjData* d) {
  SawyerTask::PlaceObjects(m, d);
  const mjtNum lid[7] = {obj_pos()[0], obj_pos()[1], kLidRestZ, std::sqrt(0.5), 0, 0,
                         std::sqrt(0.5)};
  mju_copy(d->qpos + lid_qpos_, lid, 7);
  PlaceFixture(m, box_, {goal_pos()[0], goal_pos()[1], 0.0});
}

RewardTerms BoxClose::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double grab = std::clamp((action[3] + 1.0) / 2.0, 0.0, 1.0);
  const double quat = QuatReward(s.obj_quat);
  const Vec3& hand = s.hand;
  const Vec3 lid{s.obj[0], s.obj[1], s.obj[2] + 0.02};
  const double floor =
      FunnelFloor(std::hypot(hand[0] - lid[0], hand[1] - lid[1]), 0.02, 0.04, 0.4);
  const double above_floor = AboveFloor(hand[2], floor, floor / 2.0);
  const double ready =
      HamacherProduct(above_floor, LongTailTolerance(Distance(hand, lid), 0.0, 0.02, 0.5));
  const double lifted =
      0.2 * (lid[2] > 0.04 ? 1.0 : 0.0) +
      0.8 * LongTailTolerance(WeightedDistance(s.goal, lid, {1.0, 1.0, 3.0}), 0.0, 0.05, 0.25);

  const bool success = Distance(s.obj, s.goal) < 0.08;
  const double reward =
      quat * (success ? 10.0 : 2.0 * HamacherProduct(grab, ready) + 8.0 * lifted);
  return GripRewardTerms(reward, success, ready, grab, lifted);
}

void BoxClose::InitTaskState(SawyerState& s) const { v1::InitPickPlace(s, kV1ObjHeight, kV1Lift); }

RewardTerms BoxClose::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  const double place_dist = Distance(s.obj, s.goal);
  RewardTerms terms;
  terms.reward = v1::PickPlace(s, action[3], place_dist, place_dist, 2.0);
  // v3's evaluate_state on v1's (reward, 0, 0, 0, success): no reward override
  terms.success = place_dist < 0.08;
  return terms;
}

void BoxCloseScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                 std::span<float> action) {
  SawyerObs o(env_obs);
  // Grip the handle; carry the lid with its rims 2 cm over the walls (frame
  // at 0.096) to over the box, then down onto the walls (frame at 0.06).
  o.obj1[2] += kHandleAboveLid;
  GraspAndCarryOver(o, {o.goal[0], o.goal[1], 0.06 + kHandleAboveLid},
                    0.096 + kHandleAboveLid, 0.01, action);
}

}  // namespace manyworlds::manipulation
