#include "manyworlds/manipulation/button_press_topdown.h"

#include <algorithm>
#include <cmath>

namespace manyworlds::manipulation {
namespace {

constexpr double kTravel = 0.035;  // rest to flush with the box
constexpr Vec3 kGoalOffset{0.0, 0.0, -kTravel};
// The box (root body) stands on the table, 0.115 m under the button.
constexpr Vec3 kBoxOffset{0.0, 0.0, -0.115};
constexpr double kCapHalfHeight = 0.02;
constexpr double kSuccess = 0.02;
// Closed pads reach 0.012 m below the tcp.
constexpr double kPadsBelowTcp = 0.012;
constexpr double kHoverHeight = 0.05;  // tcp above the cap top while aligning

FixtureSpec Fixture() { return {"button_box", kBoxOffset, "button_slide", 0.0, kGoalOffset}; }

Vec3 CapTop(const Vec3& button) { return {button[0], button[1], button[2] + kCapHalfHeight}; }

}  // namespace

SawyerTaskConfig ButtonPressTopdown::Config() {
  SawyerTaskConfig config;
  config.id = "button-press-topdown";
  config.description = "Sawyer arm: press a button on top of a box";
  config.xml_file = "button_press_topdown.xml";
  config.hand_init = {0.0, 0.4, 0.2};
  config.obj_low = {-0.1, 0.8, 0.115};
  config.obj_high = {0.1, 0.9, 0.115};
  UseGoalOffset(kGoalOffset, config);
  return config;
}

ButtonPressTopdown::ButtonPressTopdown(SawyerOptions options)
    : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms ButtonPressTopdown::ComputeReward(const SawyerState& s, std::span<const float>) const {
  const double tcp_to_cap = Distance(s.tcp, CapTop(s.obj));
  const double obj_to_target = std::abs(s.obj[2] - s.goal[2]);
  const double reach =
      LongTailTolerance(tcp_to_cap, 0.0, 0.02, Distance(s.tcp_init, CapTop(handle_init())));
  const double in_place = LongTailTolerance(obj_to_target, 0.0, kSuccess, kTravel);
  RewardTerms terms = FixtureReward(reach, in_place, obj_to_target <= kSuccess);
  terms.near_object = tcp_to_cap <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = s.touching_obj ? 1.0 : 0.0;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void ButtonPressTopdownScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                           std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 top = CapTop(o.obj1);
  const double xy_error = std::hypot(o.tcp[0] - top[0], o.tcp[1] - top[1]);
  const bool low = o.tcp[2] < top[2] + 0.6 * kHoverHeight;
  double tcp_z;
  if (xy_error > 0.015 || (xy_error > 0.008 && !low)) {
    tcp_z = std::max(o.tcp[2], top[2] + kHoverHeight);  // align first, never lower
  } else {
    // Pads 5 mm below the goal's cap top: pressed fully, the box stops them.
    tcp_z = o.goal[2] + kCapHalfHeight + kPadsBelowTcp - 0.005;
  }
  MoveTo(o.hand, {top[0], top[1], tcp_z + kTcpBelowHand}, 1.0, action);
}

}  // namespace manyworlds::manipulation
