#include "manyworlds/manipulation/tool/stick.h"

#include <algorithm>
#include <cmath>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

constexpr double kStickHalfLength = 0.05;
constexpr double kCanRadius = 0.06;
constexpr Vec3 kHandleToCan{0.0, 0.09, 0.0};  // the handle's middle to the can's axis
constexpr double kHandleHeight = 0.132;         // v3's insertion site above the base
constexpr double kCanMaxX = 0.406;              // the base's x + the slide's range
constexpr double kV1Lift = 0.04;                // v3's liftThresh

Vec3 Plus(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }

CagingParams StickCaging(double obj_radius) {
  return CagingParams{.obj_radius = obj_radius, .xz_thresh = 0.01, .high_density = true};
}

// v3's "held": tcp within 2 cm of the stick point, the gripper not shut and
// the stick 1 cm above its start.
bool Held(const SawyerState& s, const Vec3& stick) {
  return Distance(stick, s.tcp) < 0.02 && s.gripper_opening > 0 && stick[2] - 0.01 > s.obj_init[2];
}

// stick-pull's "inserted": the stick's end past the handle in x, within
// 4 cm of it in y and 6 cm in z.
bool Inserted(const SawyerState& s) {
  const Vec3& end = s.obj_head;
  const Vec3& handle = s.obj2;
  return end[0] >= handle[0] && std::abs(end[1] - handle[1]) <= 0.04 &&
         std::abs(end[2] - handle[2]) <= 0.06;
}

// v1 of both stick tasks (v3 writes it twice): reach the stick, lift it
// 4 cm, then a bonus toward the point v3 reads as "the object", obs[6:9]
// (the stick's height and the first two values of its quaternion, not the
// thermos: a v3 quirk kept), and, once that point is within 5 cm of the
// stick, a second one toward the goal in the plane with Gaussian widths
// exp_width and exp_width / 10. Info as v3's evaluate_state builds it from
// v1's (reward, 0, 0, goal distance, 0, 0): a tcp_to_obj of 0 counts as
// near, a tcp_open of 0 never as grasped.
RewardTerms StickRewardV1(const SawyerState& s, double grip, double exp_width) {
  const Vec3 point{s.obj[2], s.obj_quat[0], s.obj_quat[1]};
  const double goal_dist = std::hypot(point[0] - s.goal[0], point[1] - s.goal[1]);
  const double place_dist = Distance(s.obj, point);
  const double reach_dist = Distance(s.obj, s.tcp);
  const double reach = v1::Reach(s, s.obj, grip, v1::kNoXyFirst, 0.0, 0.05);
  const bool picked = s.obj[2] >= s.v1_height_target - 0.01;
  const bool dropped = v1::Dropped(s, s.obj[2], goal_dist, reach_dist);
  const double pick = v1::LiftBonus(s, s.obj[2], picked && !dropped, reach_dist < 0.1);
  double bonus = 0;
  if (picked && reach_dist < 0.1 && !dropped) {
    bonus = v1::Progress(s.v1_max_dist, place_dist);
    if (place_dist < 0.05) {
      const double g2 = goal_dist * goal_dist;
      bonus += 1000.0 * (s.v1_max_dist2 - goal_dist) +
               2000.0 * (std::exp(-g2 / exp_width) + std::exp(-g2 / (exp_width / 10.0)));
    }
    bonus = std::max(bonus, 0.0);
  }
  RewardTerms terms;
  terms.reward = reach + pick + bonus;
  terms.near_object = 1.0;
  terms.obj_to_target = goal_dist;
  return terms;
}

// The policies' view: the stick's centre and the handle's middle.
struct StickObs {
  SawyerObs o;
  Vec3 stick, handle;
  StickObs(std::span<const float> obs, const Vec3& point_to_handle) : o(obs) {
    stick = o.obj1;
    for (int i = 0; i < 3; ++i) handle[i] = obs[kObsObj2Pos + i] + point_to_handle[i];
  }
};

// Moves the stick (gripped `grip` along it from its centre) so its centre
// goes to `stick_to`; grasps it there first where it is not held.
void CarryStick(StickObs s, double grip, const Vec3& stick_to, std::span<float> action) {
  s.o.obj1 = {s.stick[0] + grip, s.stick[1], s.stick[2]};
  GraspParams params;
  params.closed_on_object = 0.75;  // the pads on the 4 cm stick read about 0.49
  params.held_distance = 0.03;
  // Once held, move the tcp by the stick's error: the stick may have slid
  // in the grip.
  const Vec3 tcp_to{s.o.tcp[0] + stick_to[0] - s.stick[0], s.o.tcp[1] + stick_to[1] - s.stick[1],
                    s.o.tcp[2] + stick_to[2] - s.stick[2]};
  GraspAndCarry(s.o, tcp_to, action, params);
}

// Where the stick's centre goes to push the can along +x until its axis is
// at `x`: in line with the axis at `height` behind the can, then forward,
// slowly (a hard push turns the stick in the grip).
Vec3 PushCanTo(const Vec3& stick, const Vec3& can, double x, double height) {
  const double behind = can[0] - kCanRadius - kStickHalfLength - 0.01;
  if (std::abs(stick[1] - can[1]) > 0.01 || std::abs(stick[2] - height) > 0.02) {
    if (stick[0] > behind) return {behind, stick[1], height};
    return {stick[0], can[1], height};
  }
  return {std::min(x - kCanRadius - kStickHalfLength + 0.005, stick[0] + 0.015), can[1], height};
}

}  // namespace

StickTask::StickTask(SawyerTaskConfig config, SawyerOptions options, const Vec3& point_offset,
                     double start_y, double goal_z)
    : SawyerTask(std::move(config), options),
      point_offset_(point_offset),
      start_y_(start_y),
      goal_z_(goal_z) {
  const sim::IdLookup ids(model(), this->config().xml_file);
  insertion_ = ids.Site("insertion");
  stick_end_ = ids.Site("stick_end");
  base_ = ids.Body("thermos_base");
  const char* slides[2] = {"thermos_x", "thermos_y"};
  for (int i = 0; i < 2; ++i) {
    slide_qpos_[i] = ids.QposAddress(slides[i]);
    slide_dof_[i] = ids.DofAddress(slides[i]);
  }
}

Vec3 StickTask::DeriveGoal(const Vec3&, const Vec3& drawn_goal) const {
  return {drawn_goal[0], drawn_goal[1], goal_z_};
}

void StickTask::PlaceObjects(mjModel* m, mjData* d) {
  SawyerTask::PlaceObjects(m, d);
  d->qpos[slide_qpos_[0]] = 0.0;
  d->qpos[slide_qpos_[1]] = start_y_;
  for (int dof : slide_dof_) d->qvel[dof] = 0.0;
}

void StickTask::RefreshTaskState(const mjData* d, SawyerState& state) const {
  state.obj2 = Plus(SitePosition(d, insertion_), point_offset_);
  state.obj_head = SitePosition(d, stick_end_);
}

void StickTask::InitTaskState(SawyerState& state) const {
  const mjtNum* base = data()->xpos + 3 * base_;
  state.obj2_init = {base[0], base[1], base[2]};
  // v1: lift 4 cm from the stick's start; the first normaliser from the
  // stick's start to the thermos's base at the lift height, the second from
  // that base to the goal in the plane
  state.v1_obj_height = state.obj_init[2];
  state.v1_height_target = state.obj_init[2] + kV1Lift;
  const Vec3 lifted{state.obj2_init[0], state.obj2_init[1], state.v1_height_target};
  state.v1_max_dist = Distance(lifted, state.obj_init) + state.v1_height_target;
  state.v1_max_dist2 =
      std::hypot(state.obj2_init[0] - state.goal[0], state.obj2_init[1] - state.goal[1]);
}

void StickTask::WriteObject2(const mjData*, float* pos_quat) const {
  for (int i = 0; i < 3; ++i) pos_quat[i] = static_cast<float>(state().obj2[i]);
  std::fill(pos_quat + 3, pos_quat + 7, 0.0f);
}

SawyerTaskConfig StickPush::Config() {
  SawyerTaskConfig config = TaskConfig(
      "stick-push", "Sawyer arm: push a thermos to the goal with a stick", "stick_push.xml",
      {{-0.08, 0.58, 0.02}, {-0.03, 0.62, 0.02}}, {{0.399, 0.55, 0.1319}, {0.401, 0.6, 0.1321}});
  config.hand_init = {0.0, 0.6, 0.2};
  config.min_obj_goal_xy = 0.1;
  return config;
}

// v3's goal is at the handle's height.
StickPush::StickPush(SawyerOptions options)
    : StickTask(Config(), options, kHandleToCan, 0.0, kHandleHeight) {}

RewardTerms StickPush::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  constexpr double kTargetRadius = 0.12;
  const Vec3 stick = Plus(s.obj, {0.015, 0.0, 0.0});
  const double tcp_to_stick = Distance(stick, s.tcp);
  const double stick_in_place = LongTailTolerance(Distance(stick, s.goal), 0.0, kTargetRadius,
                                                  Distance(s.obj_init, s.goal) - kTargetRadius);
  const double container_to_target = Distance(s.obj2, s.goal);
  const double container_in_place =
      LongTailTolerance(container_to_target, 0.0, kTargetRadius,
                        Distance(s.obj2_init, s.goal) - kTargetRadius);
  double grasped = CageObject(s, stick, action[3], StickCaging(0.04));

  RewardTerms terms;
  terms.reward = grasped;
  if (Held(s, stick)) {
    grasped = 1.0;
    terms.reward = 2.0 + 5.0 * stick_in_place + 3.0 * container_in_place;
    if (container_to_target <= kTargetRadius) terms.reward = 10.0;
  }
  const double grasp_success =
      s.touching_obj && s.gripper_opening > 0 && s.obj[2] - 0.01 > s.obj_init[2] ? 1.0 : 0.0;
  terms.success = container_to_target <= kTargetRadius && grasp_success > 0;
  terms.near_object = tcp_to_stick <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = grasp_success;
  terms.grasp_reward = grasped;
  terms.in_place_reward = stick_in_place;
  terms.obj_to_target = container_to_target;
  return terms;
}

SawyerTaskConfig StickPull::Config() {
  SawyerTaskConfig config = TaskConfig(
      "stick-pull", "Sawyer arm: pull a thermos to the goal with a stick through its handle",
      "stick_pull.xml", {{-0.1, 0.55, 0.02}, {0.0, 0.65, 0.02}},
      {{0.35, 0.45, 0.0199}, {0.45, 0.55, 0.0201}});
  config.hand_low = {-0.5, 0.35, 0.05};
  config.hand_init = {0.0, 0.6, 0.2};
  config.min_obj_goal_xy = 0.1;
  return config;
}

// v3's goal is at the stick's starting height.
StickPull::StickPull(SawyerOptions options)
    : StickTask(Config(), options, {0.0, 0.0, 0.0}, 0.09, 0.02) {}

RewardTerms StickPull::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  constexpr double kTargetRadius = 0.05;
  constexpr Vec3 kToContainer{0.05, 0.0, 0.0};
  constexpr Vec3 kZTwice{1.0, 1.0, 2.0};
  const Vec3& stick = s.obj;
  const Vec3& handle = s.obj2;
  const Vec3 container = Plus(handle, kToContainer);
  const Vec3 container_init = Plus(s.obj2_init, kToContainer);
  const double tcp_to_stick = Distance(stick, s.tcp);
  const double handle_to_target = Distance(handle, s.goal);
  const double stick_in_place =
      LongTailTolerance(WeightedDistance(stick, container, kZTwice), 0.0, kTargetRadius,
                        WeightedDistance(s.obj_init, container_init, kZTwice));
  const double stick_in_place_2 = LongTailTolerance(Distance(stick, s.goal), 0.0, kTargetRadius,
                                                    Distance(s.obj_init, s.goal));
  const double container_in_place = LongTailTolerance(
      Distance(container, s.goal), 0.0, kTargetRadius, Distance(s.obj2_init, s.goal));
  // v3 cages against its obj_init_pos, here the thermos's base.
  double grasped = GripperCagingReward(
      {s.left_pad, s.right_pad, s.tcp, stick, s.obj2_init, s.tcp_init, action[3]},
      StickCaging(0.014));
  const bool held = Held(s, stick);
  if (held) grasped = 1.0;
  const bool inserted = Inserted(s);
  const double in_place_and_grasped = HamacherProduct(grasped, stick_in_place);

  RewardTerms terms;
  terms.reward = in_place_and_grasped;
  if (held) {
    terms.reward = 1.0 + in_place_and_grasped + 5.0 * stick_in_place;
    if (inserted) {
      terms.reward = 1.0 + in_place_and_grasped + 5.0 + 2.0 * stick_in_place_2 + container_in_place;
      if (handle_to_target <= 0.12) terms.reward = 10.0;
    }
  }
  terms.success = handle_to_target <= 0.12 && inserted;
  terms.near_object = tcp_to_stick <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success =
      s.touching_obj && s.gripper_opening > 0 && stick[2] - 0.02 > s.obj2_init[2] ? 1.0 : 0.0;
  terms.grasp_reward = grasped;
  terms.in_place_reward = stick_in_place;
  terms.obj_to_target = handle_to_target;
  return terms;
}

RewardTerms StickPush::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  RewardTerms terms = StickRewardV1(s, action[3], 0.001);
  // v3's v1 success also needs grasp_success, which v1 never reports:
  // stick-push never succeeds under v1
  terms.success = false;
  return terms;
}

RewardTerms StickPull::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  RewardTerms terms = StickRewardV1(s, action[3], 0.01);
  terms.success = Distance(s.obj2, s.goal) <= 0.12 && Inserted(s);
  return terms;
}

void StickPushScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const StickObs s(env_obs, {0.0, -kHandleToCan[1], 0.0});
  const Vec3 can = Plus(s.handle, kHandleToCan);
  CarryStick(s, 0.015, PushCanTo(s.stick, can, std::min(s.o.goal[0], kCanMaxX - 0.005), 0.1),
             action);
}

void StickPullScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  // Held near its back end, the stick reaches 8.5 cm ahead of the tcp: its
  // end gets past the handle while the hand (its palm 12 cm wide) stays
  // clear of the can beside the handle.
  constexpr double kGrip = -0.035;
  constexpr double kEndPastHandle = 0.012;
  const StickObs s(env_obs, {0.0, 0.0, 0.0});
  const Vec3& stick = s.stick;
  const Vec3& handle = s.handle;
  const double end = stick[0] + kStickHalfLength;
  // The handle reaches x 0.406 at most.
  const double handle_x = std::min(s.o.goal[0], kCanMaxX - 0.002);
  const bool inserted = end >= handle[0] + 0.003 && std::abs(stick[1] - handle[1]) < 0.035 &&
                        std::abs(stick[2] - handle[2]) < 0.03;
  Vec3 to;
  if (!inserted && handle[0] < handle_x - 0.003) {
    // Push the can along +x first.
    to = PushCanTo(stick, Plus(handle, kHandleToCan), handle_x, 0.1);
  } else if (!inserted) {
    // Line up with the handle's opening behind it, then in.
    const double y = handle[1] - 0.015;
    if (std::abs(stick[1] - y) > 0.008 || std::abs(stick[2] - handle[2]) > 0.015) {
      to = end > handle[0] - 0.025 ? Vec3{handle[0] - 0.045 - kStickHalfLength, stick[1], stick[2]}
                                   : Vec3{stick[0], y, handle[2]};
    } else {
      to = {handle[0] + kEndPastHandle - kStickHalfLength, y, handle[2]};
    }
  } else {
    // Pull the handle's outer bar along -y to the goal, slowly (a hard pull
    // turns the stick in the grip).
    to = {handle[0] + kEndPastHandle - kStickHalfLength,
          std::max(s.o.goal[1] - 0.022, stick[1] - 0.015), handle[2]};
  }
  CarryStick(s, kGrip, to, action);
}

}  // namespace manyworlds::manipulation
