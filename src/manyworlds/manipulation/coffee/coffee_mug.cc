#include "manyworlds/manipulation/coffee/coffee_mug.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "manyworlds/manipulation/coffee/coffee.h"
#include "manyworlds/manipulation/object_tasks.h"
#include "manyworlds/manipulation/policy_utils.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kXyTwice{2.0, 2.0, 1.0};

// Policy. The tcp 2 cm above the foot (as v3's grasp): the pads (4.2 cm
// tall, their middle 0.9 cm above the tcp) hold the cup from 0.8 cm up to
// its rim (4.5 cm above the foot) and the palm's underside, 3 cm above the
// tcp, clears the rim by 5 mm.
constexpr double kGraspAbove = 0.02;
constexpr double kApproachAbove = 0.08;
constexpr double kApproachY = -0.01;  // in front of the cup's middle
// Carried 2 cm up (a mug dragged over the table turns in the pads), at
// most half speed.
constexpr double kCarryLift = 0.02;
constexpr float kCarrySpeed = 0.5f;
constexpr double kOverXy = 0.012;
constexpr double kAtHeight = 0.006;
constexpr double kClosedOnCup = 0.8;  // opening: 1 open, 0.66 closed on the cup
constexpr double kHeld = 0.02;

}  // namespace

SawyerTaskConfig CoffeeMugTask::Config(std::string id, std::string description,
                                       std::string xml_file, bool machine_at_goal) {
  constexpr Vec3 kAwayLow{-0.1, 0.55, -0.001}, kAwayHigh{0.1, 0.65, 0.001};
  constexpr Vec3 kAtMachineLow{-0.05, 0.7, -0.001}, kAtMachineHigh{0.05, 0.75, 0.001};
  SawyerTaskConfig config;
  config.id = std::move(id);
  config.description = std::move(description);
  config.xml_file = std::move(xml_file);
  config.hand_init = {0.0, 0.4, 0.2};
  config.obj_low = machine_at_goal ? kAwayLow : kAtMachineLow;
  config.obj_high = machine_at_goal ? kAwayHigh : kAtMachineHigh;
  config.goal_low = machine_at_goal ? kAtMachineLow : kAwayLow;
  config.goal_high = machine_at_goal ? kAtMachineHigh : kAwayHigh;
  return config;
}

CoffeeMugTask::CoffeeMugTask(SawyerTaskConfig config, bool machine_at_goal, SawyerOptions options)
    : SawyerTask(std::move(config), options), machine_at_goal_(machine_at_goal) {
  const sim::IdLookup ids(model(), this->config().xml_file);
  machine_ = ids.Body("coffee_machine");
  mug_qpos_ = ids.QposAddress("obj_free");
  mug_dof_ = ids.DofAddress("obj_free");
}

void CoffeeMugTask::PlaceObjects(mjModel* m, mjData* d) {
  coffee::PlaceMug(d, mug_qpos_, mug_dof_, obj_pos()[0], obj_pos()[1]);
  const Vec3& at_machine = machine_at_goal_ ? goal_pos() : obj_pos();
  PlaceFixture(m, machine_,
               {at_machine[0], at_machine[1] + coffee::kMugBeforeMachine, at_machine[2]});
}

void CoffeeMugTask::InitTaskState(SawyerState& s) const {
  s.v1_max_dist = std::hypot(s.obj_init[0] - s.goal[0], s.obj_init[1] - s.goal[1]);
}

RewardTerms CoffeeMugTask::ComputeRewardV1(const SawyerState& s,
                                           std::span<const float> action) const {
  const double reach_dist = Distance(s.tcp, s.obj);
  const double xy_dist = std::hypot(s.obj[0] - s.goal[0], s.obj[1] - s.goal[1]);
  double reach = -reach_dist;
  if (!machine_at_goal_) {  // coffee-pull
    const double position_norm = std::sqrt(s.obj[0] * s.obj[0] + s.obj[1] * s.obj[1] +
                                           s.tcp_init[2] * s.tcp_init[2]);
    if (position_norm < 0.05) {
      reach = -reach_dist + 0.1;
      if (reach_dist < 0.05) reach += std::max(static_cast<double>(action[3]), 0.0) / 50.0;
    } else {
      reach = -position_norm;
    }
  }
  const double bonus =
      reach_dist < 0.05 ? std::max(v1::Progress(s.v1_max_dist, xy_dist), 0.0) : 0.0;
  const double obj_to_target = Distance(s.obj, s.goal);
  return v1::StepTerms(reach + bonus, obj_to_target, 0.07);
}

RewardTerms CoffeeMugTask::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double target_to_obj = WeightedDistance(s.obj, s.goal, kXyTwice);
  const double in_place =
      LongTailTolerance(target_to_obj, 0.0, 0.05, WeightedDistance(s.obj_init, s.goal, kXyTwice));
  const double tcp_to_obj = Distance(s.tcp, s.obj);
  const CagingParams caging{.obj_radius = 0.02,
                            .object_reach_radius = 0.04,
                            .xz_thresh = 0.05,
                            .desired_gripper_effort = 0.7,
                            .medium_density = true};
  const double grasped = CageObject(s, s.obj, action[3], caging);

  double reward = HamacherProduct(grasped, in_place);
  if (tcp_to_obj < 0.04 && s.gripper_opening > 0) reward += 1.0 + 5.0 * in_place;
  const bool touching = s.touching_obj && s.gripper_opening > 0;
  return ObjectRewardTerms(s, {.reward = reward, .at_target = target_to_obj < 0.05,
                               .obj_to_target = Distance(s.obj, s.goal), .success_radius = 0.07,
                               .tcp_to_obj = tcp_to_obj, .grasped = grasped, .in_place = in_place,
                               .grasp_success = touching ? 1.0 : 0.0});
}

SawyerTaskConfig CoffeePush::Config() {
  return CoffeeMugTask::Config("coffee-push",
                               "Sawyer arm: move the mug to the front of the coffee machine",
                               "coffee_push.xml", /*machine_at_goal=*/true);
}

CoffeePush::CoffeePush(SawyerOptions options) : CoffeeMugTask(Config(), true, options) {}

SawyerTaskConfig CoffeePull::Config() {
  return CoffeeMugTask::Config("coffee-pull",
                               "Sawyer arm: move the mug away from the coffee machine",
                               "coffee_pull.xml", /*machine_at_goal=*/false);
}

CoffeePull::CoffeePull(SawyerOptions options) : CoffeeMugTask(Config(), false, options) {}

void CoffeeMugScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 grasp{o.obj1[0], o.obj1[1], o.obj1[2] + kGraspAbove};
  const Vec3 approach{grasp[0], grasp[1] + kApproachY, grasp[2]};
  const auto hand_for_tcp = [](double x, double y, double z) {
    return Vec3{x, y, z + kTcpBelowHand};
  };
  if (o.gripper_opening < kClosedOnCup && Distance(o.tcp, grasp) < kHeld) {
    MoveTo(o.hand, hand_for_tcp(o.goal[0], o.goal[1], o.goal[2] + kGraspAbove + kCarryLift), 1.0,
           action);
    for (int i = 0; i < 3; ++i) action[i] = std::clamp(action[i], -kCarrySpeed, kCarrySpeed);
    return;
  }
  const double xy_error = std::hypot(o.tcp[0] - approach[0], o.tcp[1] - approach[1]);
  if (xy_error > kOverXy) {
    MoveTo(o.hand, hand_for_tcp(approach[0], approach[1], grasp[2] + kApproachAbove), -1.0, action);
  } else if (o.tcp[2] - grasp[2] > kAtHeight) {
    MoveTo(o.hand, hand_for_tcp(approach[0], approach[1], grasp[2]), -1.0, action);
  } else {
    MoveTo(o.hand, hand_for_tcp(approach[0], approach[1], grasp[2]), 1.0, action);
  }
}

}  // namespace manyworlds::manipulation
