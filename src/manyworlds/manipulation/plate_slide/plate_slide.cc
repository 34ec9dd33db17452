#include "manyworlds/manipulation/plate_slide/plate_slide.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/manipulation/push_from_behind.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kTargetRadius = 0.05;
constexpr Vec3 kChannel{0.0, 0.6, 0.015};

SawyerTaskConfig PlateConfig(const char* id, const char* description, const char* xml,
                             const Vec3& obj_init, const Vec3& goal_low, const Vec3& goal_high) {
  SawyerTaskConfig config;
  config.id = id;
  config.description = description;
  config.xml_file = xml;
  config.obj_low = obj_init;
  config.obj_high = obj_init;
  config.goal_low = goal_low;
  config.goal_high = goal_high;
  config.min_obj_goal_xy = 0.0;  // v3 draws without a rule
  return config;
}

}  // namespace

PlateSlideTask::PlateSlideTask(SawyerTaskConfig config, PlateSlideVariant variant,
                               SawyerOptions options)
    : SawyerTask(std::move(config), options), variant_(variant) {
  const sim::IdLookup ids(model(), this->config().xml_file);
  frame_ = ids.Body("cage");
  plate_x_ = ids.QposAddress("plate_x");
  plate_y_ = ids.QposAddress("plate_y");
}

void PlateSlideTask::PlaceObjects(mjModel* m, mjData* d) {
  d->qpos[plate_x_] = variant_.plate_start[0] - kChannel[0];
  d->qpos[plate_y_] = variant_.plate_start[1] - kChannel[1];
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_qposadr[j] == plate_x_ || m->jnt_qposadr[j] == plate_y_) {
      d->qvel[m->jnt_dofadr[j]] = 0;
      d->qacc_warmstart[m->jnt_dofadr[j]] = 0;
    }
  }
  PlaceFixture(m, frame_, variant_.frame_at_goal ? goal_pos() : variant_.frame);
}

void PlateSlideTask::InitTaskState(SawyerState& s) const {
  s.v1_max_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
}

RewardTerms PlateSlideTask::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  const double pull_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  return v1::ReachThenProgressStep(s, Distance(s.obj, s.tcp), pull_dist, 0.07);
}

RewardTerms PlateSlideTask::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double obj_to_target = Distance(s.obj, s.goal);
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const double less = variant_.low_push_reward ? kTargetRadius : 0.0;
  const double in_place =
      LongTailTolerance(obj_to_target, 0.0, kTargetRadius, Distance(s.obj_init, s.goal) - less);
  const double grasped =
      LongTailTolerance(tcp_to_obj, 0.0, kTargetRadius, Distance(s.tcp_init, s.obj_init) - less);
  RewardTerms terms;
  if (variant_.low_push_reward) {
    terms.reward = 1.5 * grasped;
    if (s.tcp[2] <= 0.03 && tcp_to_obj < 0.07) terms.reward = 2.0 + 7.0 * in_place;
  } else {
    terms.reward = 8.0 * HamacherProduct(grasped, in_place);
  }
  if (obj_to_target < kTargetRadius) terms.reward = 10.0;
  terms.success = obj_to_target <= 0.07;
  terms.near_object = tcp_to_obj <= 0.03 ? 1.0 : 0.0;
  terms.grasp_reward = grasped;
  terms.in_place_reward = in_place;
  terms.obj_to_target = obj_to_target;
  return terms;
}

PlateSlide::PlateSlide(SawyerOptions options)
    : PlateSlideTask(Config(), {{0.0, 0.6, 0.015}, true, {}, false}, options) {}

SawyerTaskConfig PlateSlide::Config() {
  return PlateConfig("plate-slide", "Sawyer arm: slide a plate forward into a goal frame",
                     "plate_slide.xml", {0.0, 0.6, 0.0}, {-0.1, 0.85, 0.0}, {0.1, 0.9, 0.0});
}

PlateSlideSide::PlateSlideSide(SawyerOptions options)
    : PlateSlideTask(Config(), {{0.0, 0.6, 0.015}, false, {-0.3, 0.6, 0.0}, true}, options) {}

SawyerTaskConfig PlateSlideSide::Config() {
  return PlateConfig("plate-slide-side", "Sawyer arm: slide a plate sideways into a goal frame",
                     "plate_slide_side.xml", {0.0, 0.6, 0.0}, {-0.3, 0.54, 0.0},
                     {-0.25, 0.66, 0.0});
}

PlateSlideBack::PlateSlideBack(SawyerOptions options)
    : PlateSlideTask(Config(), {{0.0, 0.75, 0.015}, false, {0.0, 0.85, 0.0}, true}, options) {}

SawyerTaskConfig PlateSlideBack::Config() {
  return PlateConfig("plate-slide-back",
                     "Sawyer arm: slide a plate back out of its frame toward the robot",
                     "plate_slide_back.xml", {0.0, 0.85, 0.0}, {-0.1, 0.6, 0.015},
                     {0.1, 0.6, 0.015});
}

PlateSlideBackSide::PlateSlideBackSide(SawyerOptions options)
    : PlateSlideTask(Config(), {{-0.15, 0.6, 0.015}, false, {-0.25, 0.6, 0.0}, true}, options) {}

SawyerTaskConfig PlateSlideBackSide::Config() {
  return PlateConfig("plate-slide-back-side",
                     "Sawyer arm: slide a plate sideways out of its frame",
                     "plate_slide_back_side.xml", {-0.25, 0.6, 0.0}, {-0.05, 0.6, 0.015},
                     {0.15, 0.6, 0.015});
}

void PlateSlideScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  PushFromBehind(o, o.obj1, o.goal, PushParams{}, action);
}

}  // namespace manyworlds::manipulation
