#include "manyworlds/manipulation/door_close.h"

#include "manyworlds/manipulation/door_fixture.h"

namespace manyworlds::manipulation {
namespace {

constexpr Vec3 kGoalOffset{0.2, -0.2, 0.0};
constexpr double kSuccess = 0.08;
constexpr double kStartAngle = -1.6;  // hinge position at reset (open)
// Grasp the grip 5 mm above its middle: the pads then clear its arm.
constexpr Vec3 kGraspAbove{0.0, 0.0, 0.005};
// Swing at 0.6 cm per step: the handle slides along the pads (held by
// friction only) where the door's motion is along x.
constexpr double kCarrySpeed = 0.6;
// Turn slightly past shut: the hinge limit stops the door there.
constexpr double kOvershoot = 0.1;

FixtureSpec Fixture() {
  return {"door_frame", door::kFrameOffset, "door_hinge", kStartAngle, kGoalOffset};
}

}  // namespace

SawyerTaskConfig DoorClose::Config() {
  SawyerTaskConfig config;
  config.id = "door-close";
  config.description = "Sawyer arm: swing an open door shut";
  config.xml_file = "door_close.xml";
  config.hand_init = {-0.5, 0.6, 0.2};
  config.obj_low = {0.0, 0.85, 0.15};
  config.obj_high = {0.1, 0.95, 0.15};
  UseGoalOffset(kGoalOffset, config);
  return config;
}

DoorClose::DoorClose(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms DoorClose::ComputeReward(const SawyerState& s, std::span<const float>) const {
  return MoveHandleReward(s, handle_init(), kSuccess);
}

void DoorCloseScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 obj{o.goal[0] - kGoalOffset[0], o.goal[1] - kGoalOffset[1],
                 o.goal[2] - kGoalOffset[2]};
  const Vec3 grasp{o.obj1[0] + kGraspAbove[0], o.obj1[1] + kGraspAbove[1],
                   o.obj1[2] + kGraspAbove[2]};
  const Vec3 next =
      NextPointOnArc(grasp, door::Hinge(obj), 2, door::ClosedHandleAngle() + kOvershoot);
  GraspAndMove(o, grasp, next, -1.0, action, kCarrySpeed);
}

}  // namespace manyworlds::manipulation
