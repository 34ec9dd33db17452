#include "manyworlds/manipulation/door_open.h"

#include <cmath>

#include "manyworlds/manipulation/door_fixture.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{-0.3, -0.45, 0.0};
constexpr double kSuccessX = 0.08;
// Grasp the grip 5 mm above its middle: the pads then clear its arm.
constexpr Vec3 kGraspAbove{0.0, 0.0, 0.005};
// Swing at 0.6 cm per step: the handle slides along the pads (held by
// friction only) where the door's motion is along x.
constexpr double kCarrySpeed = 0.6;
// Turn past the goal (success comes near -1.7 rad of hinge travel), short
// of the hinge's limit.
constexpr double kTurnTo = door::kMaxOpen - 0.2;

FixtureSpec Fixture() { return {"door_frame", door::kFrameOffset, "door_hinge", 0.0, kGoalOffset}; }

}  // namespace

SawyerTaskConfig DoorOpen::Config() {
  SawyerTaskConfig config;
  config.id = "door-open";
  config.description = "Sawyer arm: swing a door open by its handle";
  config.xml_file = "door_open.xml";
  config.hand_init = {0.0, 0.6, 0.2};
  config.obj_low = {0.0, 0.85, 0.15};
  config.obj_high = {0.1, 0.95, 0.15};
  UseGoalOffset(kGoalOffset, config);
  return config;
}

DoorOpen::DoorOpen(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms DoorOpen::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double tcp_to_handle = Distance(s.tcp, s.obj);
  const double x_error = std::abs(s.obj[0] - s.goal[0]);
  const double reach =
      LongTailTolerance(tcp_to_handle, 0.0, 0.02, Distance(s.tcp_init, handle_init()));
  const double engaged = HamacherProduct(reach, GripEffort(action));
  const double in_place =
      LongTailTolerance(x_error, 0.0, kSuccessX, std::abs(handle_init()[0] - s.goal[0]));
  RewardTerms terms = FixtureReward(engaged, in_place, x_error <= kSuccessX);
  terms.near_object = tcp_to_handle <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = s.touching_obj && action[3] > 0 ? 1.0 : 0.0;
  terms.obj_to_target = x_error;
  return terms;
}

void DoorOpenScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                 std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 obj{o.goal[0] - kGoalOffset[0], o.goal[1] - kGoalOffset[1],
                 o.goal[2] - kGoalOffset[2]};
  const Vec3 grasp{o.obj1[0] + kGraspAbove[0], o.obj1[1] + kGraspAbove[1],
                   o.obj1[2] + kGraspAbove[2]};
  const Vec3 next = NextPointOnArc(grasp, door::Hinge(obj), 2, door::ClosedHandleAngle() - kTurnTo);
  GraspAndMove(o, grasp, next, -1.0, action, kCarrySpeed);
}

}  // namespace manyworlds::manipulation
