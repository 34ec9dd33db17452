#include "manyworlds/manipulation/tool/hammer.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoal{0.24, 0.74, 0.11};       // v3's site "goal" on its fixed box
constexpr Vec3 kHeadOffset{0.16, 0.06, 0.0};  // v3's hammer_head - hammer
constexpr double kHandleHalfLength = 0.07;    // v3's HAMMER_HANDLE_LENGTH / 2
constexpr double kDrivenIn = 0.09;
constexpr double kV1Lift = 0.09;  // v3's liftThresh
// The rest pose on the table (head and handle end down): height of the
// handle's centre and tilt about y (head up), as v3's hammer settles.
constexpr double kRestHeight = 0.0284;
constexpr double kRestTilt = 0.0601;
// Our hammer's centre of mass along the handle from its centre (the grip).
constexpr double kGrip = 0.04;

}  // namespace

SawyerTaskConfig Hammer::Config() {
  SawyerTaskConfig config = TaskConfig("hammer", "Sawyer arm: hammer a nail into a block",
                                       "hammer.xml", {{-0.1, 0.4, 0.0}, {0.1, 0.5, 0.0}},
                                       {{0.2399, 0.7399, 0.109}, {0.2401, 0.7401, 0.111}});
  config.hand_init = {0.0, 0.4, 0.2};
  config.min_obj_goal_xy = 0.0;
  config.obj_quat = QuatLayout::kWxyz;
  return config;
}

Hammer::Hammer(SawyerOptions options) : SawyerTask(Config(), options) {
  const sim::IdLookup ids(model(), config().xml_file);
  obj_qpos_ = ids.QposAddress("obj_free");
  obj_dof_ = ids.DofAddress("obj_free");
  nail_body_ = ids.Body("nail");
  nail_qpos_ = ids.QposAddress("nail_slide");
  nail_dof_ = ids.DofAddress("nail_slide");
  head_geom_ = ids.Geom("hammer_neck");
}

Vec3 Hammer::DeriveGoal(const Vec3&, const Vec3&) const { return kGoal; }

void Hammer::PlaceObjects(mjModel*, mjData* d) {
  const mjtNum rest[7] = {obj_pos()[0], obj_pos()[1], kRestHeight, std::cos(kRestTilt / 2), 0,
                          -std::sin(kRestTilt / 2), 0};
  mju_copy(d->qpos + obj_qpos_, rest, 7);
  mju_zero(d->qvel + obj_dof_, 6);
  d->qpos[nail_qpos_] = 0;
  d->qvel[nail_dof_] = 0;
}

void Hammer::RefreshTaskState(const mjData* d, SawyerState& state) const {
  state.joint_qpos = d->qpos[nail_qpos_];
  const mjtNum* nail = d->xpos + 3 * nail_body_;
  state.obj2 = {nail[0], nail[1], nail[2]};
  // v1 reads the head's and the nail head's positions (our nail's frame is
  // its head's centre)
  const mjtNum* head = d->geom_xpos + 3 * head_geom_;
  state.obj_head = {head[0], head[1], head[2]};
  state.obj2_head = state.obj2;
}

void Hammer::WriteObject2(const mjData* d, float* pos_quat) const {
  for (int i = 0; i < 3; ++i) pos_quat[i] = static_cast<float>(state().obj2[i]);
  for (int i = 0; i < 4; ++i) pos_quat[3 + i] = static_cast<float>(d->xquat[4 * nail_body_ + i]);
}

RewardTerms Hammer::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  Vec3 threshed = s.obj;
  if (std::abs(s.obj[0] - s.hand[0]) < kHandleHalfLength) threshed[0] = s.hand[0];
  double quat_error = 0;
  const double level[4] = {1, 0, 0, 0};
  for (int i = 0; i < 4; ++i) quat_error += (s.obj_quat[i] - level[i]) * (s.obj_quat[i] - level[i]);
  const double level_reward = std::max(1.0 - std::sqrt(quat_error) / 0.4, 0.0);
  const CagingParams caging{.pad_success_thresh = 0.02, .xz_thresh = 0.01, .high_density = true};
  const double grab = CageObject(s, threshed, action[3], caging);
  const Vec3 head{s.obj[0] + kHeadOffset[0], s.obj[1] + kHeadOffset[1], s.obj[2] + kHeadOffset[2]};
  const double in_place = 0.1 * (head[2] > 0.02 ? 1.0 : 0.0) +
                          0.9 * LongTailTolerance(Distance(s.goal, head), 0.0, 0.02, 0.2);

  const bool success = s.joint_qpos > kDrivenIn;
  double reward = (2.0 * grab + 6.0 * in_place) * level_reward;
  if (success && reward > 5.0) reward = 10.0;
  return GripRewardTerms(reward, success, level_reward, grab, in_place);
}

void Hammer::InitTaskState(SawyerState& s) const {
  // v3 reads its lift reference and normaliser with the hammer at its drawn
  // height, 0 (the obj_init z), before it settles onto the rest pose ours
  // starts in; its normaliser measures from the hammer's own start, not the
  // nail's (obj_init_pos is the hammer's there)
  s.v1_obj_height = s.obj_init[2];
  s.v1_height_target = s.obj_init[2] + kV1Lift;
  const Vec3 lifted{s.obj_init[0], s.obj_init[1], s.v1_height_target};
  s.v1_max_dist = Distance(lifted, s.obj_init) + s.v1_height_target +
                  std::abs(s.obj_init[1] - s.goal[1]);
}

RewardTerms Hammer::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  const Vec3& head = s.obj_head;
  const Vec3& nail = s.obj2_head;
  const double hammer_dist = Distance(nail, head);
  const double screw_dist = std::abs(nail[1] - s.goal[1]);
  const double reach_dist = Distance(s.obj, s.tcp);
  const double reach = v1::Reach(s, s.obj, action[3], v1::kNoXyFirst, 0.0, 0.05);
  const bool picked = s.obj[2] >= s.v1_height_target - 0.01;
  const bool dropped = v1::Dropped(s, s.obj[2], hammer_dist, reach_dist);
  const double pick = v1::LiftBonus(s, s.obj[2], picked && !dropped, reach_dist < 0.1);
  double hammer = 0;
  if (picked && reach_dist < 0.1 && !dropped) {
    hammer = std::max(v1::Progress(s.v1_max_dist, hammer_dist + screw_dist), 0.0);
  }
  RewardTerms terms;
  terms.reward = reach + pick + hammer;
  // v3's evaluate_state on v1's (reward, 0, 0, 0, nail driven in)
  terms.success = s.joint_qpos > kDrivenIn;
  return terms;
}

void HammerScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                               std::span<float> action) {
  SawyerObs o(env_obs);
  const Vec3 hammer = o.obj1;
  const Vec3 nail{env_obs[kObsObj2Pos], env_obs[kObsObj2Pos + 1], env_obs[kObsObj2Pos + 2]};
  // Grip and steer by the handle's point above the centre of mass.
  o.obj1 = {hammer[0] + kGrip, hammer[1], hammer[2]};
  // Where the hammer's centre should go: level with the nail, the head's
  // boss in line with it, 6 cm short of the nail's head until lined up;
  // then up to the nail fast and through it slowly (a hard blow would turn
  // the hammer in the grip).
  const double head_x = kGoal[0] - kHeadOffset[0];
  const bool lined_up =
      std::abs(hammer[0] - head_x) < 0.01 && std::abs(hammer[2] - nail[2]) < 0.015;
  const double touching = nail[1] - 0.072 - 0.009;  // the face's and the nail head's half-widths
  double y = std::min(hammer[1], touching - 0.06);
  if (lined_up) y = hammer[1] < touching - 0.015 ? touching - 0.005 : hammer[1] + 0.01;
  GraspParams params;
  params.closed_on_object = 0.5;
  GraspAndCarry(o, {head_x + kGrip, y, nail[2]}, action, params);
}

}  // namespace manyworlds::manipulation
