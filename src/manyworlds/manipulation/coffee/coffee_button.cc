#include "manyworlds/manipulation/coffee/coffee_button.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "manyworlds/manipulation/coffee/coffee.h"
#include "manyworlds/manipulation/reward_v1.h"
#include "manyworlds/sim/ids.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{0.0, -0.19, 0.3};
constexpr double kMaxDist = 0.03;  // v3's max_dist, the button's travel

FixtureSpec Fixture() { return {"coffee_machine", {}, "button_slide", 0.0, kGoalOffset}; }

}  // namespace

SawyerTaskConfig CoffeeButton::Config() {
  SawyerTaskConfig config =
      TaskConfig("coffee-button", "Sawyer arm: push the coffee machine's button",
                 "coffee_button.xml", {{-0.1, 0.8, -0.001}, {0.1, 0.9, 0.001}});
  config.hand_init = {0.0, 0.4, 0.2};
  config.obj_quat = QuatLayout::kWxyz;
  config.obj_quat_body = "coffee_machine";
  UseGoalOffset(kGoalOffset, config);
  // v3's goal_space: the object range + (-+0.001, -0.19, 0.299 / 0.301), 1 mm
  // wider than where the goals lie in x and z.
  config.goal_space = Range3{{-0.101, 0.61, 0.298}, {0.101, 0.71, 0.302}};
  return config;
}

CoffeeButton::CoffeeButton(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {
  const sim::IdLookup ids(model(), config().xml_file);
  mug_qpos_ = ids.QposAddress("mug_free");
  mug_dof_ = ids.DofAddress("mug_free");
}

void CoffeeButton::PlaceObjects(mjModel* m, mjData* d) {
  ArticulatedTask::PlaceObjects(m, d);
  coffee::PlaceMug(d, mug_qpos_, mug_dof_, obj_pos()[0], obj_pos()[1] - coffee::kMugBeforeMachine);
}

void CoffeeButton::InitTaskState(SawyerState& s) const {
  ArticulatedTask::InitTaskState(s);
  s.obj_to_target_init = kMaxDist;
  s.v1_max_dist = std::abs(s.obj[1] - s.goal[1]);  // v3's maxDist
}

RewardTerms CoffeeButton::ComputeRewardV1(const SawyerState& s, std::span<const float>) const {
  return FrontButtonRewardV1(s, 0.02);
}

RewardTerms CoffeeButton::ComputeReward(const SawyerState& s, std::span<const float>) const {
  return ButtonPressReward(s);
}

}  // namespace manyworlds::manipulation
