#include "manyworlds/manipulation/peg/nut.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "manyworlds/manipulation/grasp_policy.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

// The nut lying flat, turned 90 degrees about z (v3's RoundNut).
constexpr double kHalfSqrt2 = 0.70710678118654752;
// v3 compares obs[7:11] with this rounded quaternion.
constexpr double kFlatQuat[4] = {0.707, 0.0, 0.0, 0.707};
constexpr double kHandleLength = 0.02;  // v3's WRENCH_HANDLE_LENGTH
constexpr double kHandleToCentre = 0.13;
// The ring's centre lying on the table (its tube's radius, less the
// contacts' settling).
constexpr double kRestHeight = 0.019;
constexpr double kAssemblyPegBelowGoal = 0.05;
constexpr double kDisassembleGoalAbove = 0.15;
constexpr double kDisassemblePegAbove = 0.03;  // the peg's centre above the nut
// v1: v3's obj_height for assembly (its handle's height at reset, its nut
// placed 1 mm above our rest pose) and lift heights (liftThresh).
constexpr double kV1AssemblyObjHeight = 0.0199455;
constexpr double kV1AssemblyLift = 0.1;
constexpr double kV1DisassembleLift = 0.05;

double QuatReward(const SawyerState& s) {
  double sum = 0;
  for (int i = 0; i < 4; ++i) sum += (s.obj_quat[i] - kFlatQuat[i]) * (s.obj_quat[i] - kFlatQuat[i]);
  return std::max(1.0 - std::sqrt(sum) / 0.4, 0.0);
}

double GrabReward(const SawyerState& s, float gripper_action, bool medium_density) {
  Vec3 handle = s.obj;
  if (std::abs(handle[0] - s.hand[0]) < kHandleLength / 2.0) handle[0] = s.hand[0];
  const CagingParams caging{.pad_success_thresh = 0.02,
                            .xz_thresh = 0.01,
                            .high_density = !medium_density,
                            .medium_density = medium_density};
  return CageObject(s, handle, gripper_action, caging);
}

RewardTerms NutReward(const SawyerState& s, double grab, double in_place, bool success) {
  const double quat = QuatReward(s);
  return GripRewardTerms(success ? 10.0 : (2.0 * grab + 6.0 * in_place) * quat, success, quat,
                         grab, in_place);
}

// The ring's centre from the observed handle and the nut's (w, x, y, z).
Vec3 RingCentre(std::span<const float> env_obs) {
  mjtNum q[4], along[3];
  for (int i = 0; i < 4; ++i) q[i] = env_obs[kObsObj1Quat + i];
  const mjtNum local[3] = {0.0, kHandleToCentre, 0.0};
  mju_normalize4(q);
  mju_rotVecQuat(along, local, q);
  return {env_obs[kObsObj1Pos] + along[0], env_obs[kObsObj1Pos + 1] + along[1],
          env_obs[kObsObj1Pos + 2] + along[2]};
}


}  // namespace

NutTask::NutTask(SawyerTaskConfig config, double peg_below_goal, SawyerOptions options)
    : SawyerTask(std::move(config), options), peg_below_goal_(peg_below_goal) {
  const sim::IdLookup ids(model(), this->config().xml_file);
  nut_qpos_ = model()->jnt_qposadr[model()->body_jntadr[ids.Body("obj")]];
  peg_ = ids.Body("peg");
  handle_ = ids.Site("obj_point");
  nut_centre_ = ids.Site("nut_centre");
}

void NutTask::PlaceObjects(mjModel* m, mjData* d) {
  SawyerTask::PlaceObjects(m, d);
  // SawyerTask placed the nut upright at obj_pos(); turn it as v3's lies,
  // resting on the table (v3 drops it from obj_pos's height, 1 or 6 mm).
  const mjtNum turned[4] = {kHalfSqrt2, 0.0, 0.0, kHalfSqrt2};
  mju_copy4(d->qpos + nut_qpos_ + 3, turned);
  d->qpos[nut_qpos_ + 2] = kRestHeight;
  const Vec3& goal = goal_pos();
  PlaceFixture(m, peg_, {goal[0], goal[1], goal[2] - peg_below_goal_});
}

void NutTask::RefreshTaskState(const mjData* d, SawyerState& state) const {
  state.obj = SitePosition(d, handle_);
  state.obj_head = SitePosition(d, nut_centre_);
}

SawyerTaskConfig Assembly::Config() {
  SawyerTaskConfig config = TaskConfig(
      "assembly", "Sawyer arm: pick up a nut by its handle and put it onto a peg", "assembly.xml",
      {{0.0, 0.6, 0.02}, {0.0, 0.6, 0.02}}, {{-0.1, 0.75, 0.1}, {0.1, 0.85, 0.1}});
  config.hand_init = {0.0, 0.6, 0.2};
  config.min_obj_goal_xy = 0.1;
  config.obj_quat = QuatLayout::kWxyz;
  return config;
}

Assembly::Assembly(SawyerOptions options) : NutTask(Config(), kAssemblyPegBelowGoal, options) {}

RewardTerms Assembly::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const Vec3& ring = s.obj_head;
  const double ex = s.goal[0] - ring[0], ey = s.goal[1] - ring[1], ez = s.goal[2] - ring[2];
  const double radius = std::hypot(ex, ey);
  const bool success = radius < 0.02 && ez > 0.0;
  // A funnel round the peg: the ring should be high while off the axis.
  const double threshold = success ? 0.02 : 0.01;
  const double height = radius > threshold ? 0.02 * std::log(radius - threshold) + 0.2 : 0.0;
  const double dz = 3.0 * (height - ring[2]);
  const bool lifted = ring[2] > 0.02 || radius < threshold;
  const double in_place =
      0.1 * (lifted ? 1.0 : 0.0) +
      0.9 * LongTailTolerance(std::sqrt(ex * ex + ey * ey + dz * dz), 0.0, 0.02, 0.4);
  return NutReward(s, GrabReward(s, action[3], /*medium_density=*/true), in_place, success);
}

SawyerTaskConfig Disassemble::Config() {
  SawyerTaskConfig config =
      TaskConfig("disassemble", "Sawyer arm: lift a nut by its handle off a peg", "disassemble.xml",
                 {{0.0, 0.6, 0.025}, {0.1, 0.75, 0.02501}},
                 {{0.0, 0.6, 0.025 + kDisassembleGoalAbove},
                  {0.1, 0.75, 0.02501 + kDisassembleGoalAbove}});
  config.hand_init = {0.0, 0.4, 0.2};
  config.goal_z_at_object = false;
  config.min_obj_goal_xy = 0.0;
  config.obj_quat = QuatLayout::kWxyz;
  // v3's goal_space: its drawn (throw-away) goal's range 5 mm up, x from
  // -0.1 where the goals (above the nut) start at 0.
  config.goal_space = Range3{{-0.1, 0.6, 0.1749}, {0.1, 0.75, 0.1751}};
  return config;
}

Disassemble::Disassemble(SawyerOptions options)
    : NutTask(Config(), kDisassembleGoalAbove - kDisassemblePegAbove, options) {}

TaskState Disassemble::DoSampleTaskState(Rng& rng) {
  // v3's draw: the nut and a goal in (-0.1, 0.6, 0.1699)-(0.1, 0.75, 0.1701),
  // both redrawn while within 0.1 m in xy; the goal is then dropped.
  const SawyerTaskConfig& c = config();
  Vec3 obj{}, drawn{};
  do {
    for (int i = 0; i < 3; ++i) obj[i] = rng.Uniform(c.obj_low[i], c.obj_high[i]);
    drawn = {rng.Uniform(-0.1, 0.1), rng.Uniform(0.6, 0.75), rng.Uniform(0.1699, 0.1701)};
  } while (std::hypot(obj[0] - drawn[0], obj[1] - drawn[1]) < 0.1);
  const Vec3 goal = DeriveGoal(obj, drawn);
  return TaskState{id(), {{"obj_pos", std::vector<double>(obj.begin(), obj.end())},
                          {"goal_pos", std::vector<double>(goal.begin(), goal.end())}}};
}

Vec3 Disassemble::DeriveGoal(const Vec3& obj, const Vec3&) const {
  return {obj[0], obj[1], obj[2] + kDisassembleGoalAbove};
}

RewardTerms Disassemble::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const Vec3& ring = s.obj_head;
  const Vec3 above{s.goal[0], s.goal[1], s.goal[2] + 0.1};
  const bool lifted = ring[2] > 0.02;
  const double in_place = 0.1 * (lifted ? 1.0 : 0.0) +
                          0.9 * LongTailTolerance(Distance(above, ring), 0.0, 0.02, 0.2);
  return NutReward(s, GrabReward(s, action[3], /*medium_density=*/false), in_place,
                   s.obj[2] > s.goal[2]);
}

void Assembly::InitTaskState(SawyerState& s) const {
  v1::InitPickPlace(s, kV1AssemblyObjHeight, kV1AssemblyLift);
}

RewardTerms Assembly::ComputeRewardV1(const SawyerState& s, std::span<const float> action) const {
  const Vec3& ring = s.obj_head;  // v3's RoundNut body
  const double reach_dist = Distance(s.obj, s.tcp);
  const double reach = v1::Reach(s, s.obj, action[3], 0.04, 1.0, 0.04);
  const double place_dist = std::hypot(ring[0] - s.goal[0], ring[1] - s.goal[1]);
  const double sink = std::abs(ring[2] - s.v1_obj_height);  // v3's placingDistFinal
  const bool picked = ring[2] >= s.v1_height_target - 0.01 && reach_dist < 0.03;
  const bool dropped = v1::Dropped(s, ring[2], place_dist, reach_dist);
  const bool over_peg =
      std::abs(ring[0] - s.goal[0]) < 0.03 && std::abs(ring[1] - s.goal[1]) < 0.03;
  const double pick =
      v1::LiftBonus(s, ring[2], over_peg || (picked && !dropped), reach_dist < 0.04);
  double place = 0;
  if (over_peg || (picked && reach_dist < 0.04 && !dropped)) {
    place = v1::Progress(s.v1_max_dist, place_dist);
    // over the peg, lowering the ring back to its start height pays more
    if (over_peg) {
      place += 2000.0 * (s.v1_height_target - sink) +
               2000.0 * (std::exp(-sink * sink / 0.003) + std::exp(-sink * sink / 0.0003));
    }
    place = std::max(place, 0.0);
  }
  RewardTerms terms;
  terms.reward = reach + pick + place;
  // v3's evaluate_state on v1's (reward, 0, 0, 0, success)
  terms.success = over_peg && sink <= 0.04;
  return terms;
}

void Disassemble::InitTaskState(SawyerState& s) const {
  v1::InitPickPlace(s, s.obj_init[2], kV1DisassembleLift);
}

RewardTerms Disassemble::ComputeRewardV1(const SawyerState& s,
                                         std::span<const float> action) const {
  const Vec3& ring = s.obj_head;  // v3's RoundNut body
  const double reach_dist = Distance(s.obj, s.tcp);
  double reach = v1::Reach(s, s.obj, action[3], 0.04, 2.0, 0.04);
  const double place_dist = Distance(s.obj, s.goal);
  const bool picked = s.obj[2] >= s.v1_height_target - 0.01 && reach_dist < 0.04;
  const bool dropped = v1::Dropped(s, s.obj[2], place_dist, reach_dist);
  double pick = v1::LiftBonus(s, s.obj[2], picked && !dropped, reach_dist < 0.04);
  double place = 0;
  if (picked && reach_dist < 0.03 && !dropped) {
    place = std::max(v1::Progress(s.v1_max_dist, place_dist), 0.0);
  }
  // v3: off the peg (the ring 5 cm from its axis, which stands at the
  // nut's start), no reach term and the full lift bonus
  if (std::abs(ring[0] - s.obj_init[0]) > 0.05 || std::abs(ring[1] - s.obj_init[1]) > 0.05) {
    reach = 0.0;
    pick = 100.0 * s.v1_height_target;
  }
  RewardTerms terms;
  terms.reward = reach + pick + place;
  terms.success = s.obj[2] > s.goal[2];
  return terms;
}

void AssemblyScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                 std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 ring = RingCentre(env_obs);
  const Vec3& top = o.goal;  // the peg's top
  // Carry the ring 5 cm above the top until it is over the axis, then lower
  // it round the peg.
  const double off_axis = std::hypot(ring[0] - top[0], ring[1] - top[1]);
  const bool over = off_axis < 0.006;
  const bool clear = ring[2] > top[2] + 0.035;
  Vec3 ring_to{top[0], top[1], top[2] + 0.05};
  if (over) {
    ring_to[2] = top[2] - 0.05;
  } else if (!clear && off_axis > 0.015) {
    ring_to = {ring[0], ring[1], top[2] + 0.05};
  }
  Vec3 carry_to;
  for (int i = 0; i < 3; ++i) carry_to[i] = o.tcp[i] + ring_to[i] - ring[i];
  GraspAndCarry(o, carry_to, action);
}

void DisassembleScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                    std::span<float> action) {
  const SawyerObs o(env_obs);
  // Straight up, 5 cm past the goal height.
  GraspAndCarry(o, {o.obj1[0], o.obj1[1], o.goal[2] + 0.05}, action);
}

}  // namespace manyworlds::manipulation
