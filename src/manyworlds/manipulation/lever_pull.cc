#include "manyworlds/manipulation/lever_pull.h"

#include <cmath>
#include <numbers>

namespace manyworlds::manipulation {
namespace {

constexpr double kArm = 0.2;  // axis to grip (lever_pull.xml)
constexpr Vec3 kGoalOffset{0.08, 0.0, 0.2 + kArm};
constexpr double kUp = std::numbers::pi / 2;
constexpr double kSuccess = std::numbers::pi / 24;
// Hold the grip beside the arm, which meets it in the middle.
constexpr Vec3 kGraspBeside{0.035, 0.0, 0.0};

FixtureSpec Fixture() { return {"lever_base", {}, "lever_hinge", 0.0, kGoalOffset}; }

Vec3 GraspPoint(const Vec3& grip) {
  return {grip[0] + kGraspBeside[0], grip[1] + kGraspBeside[1], grip[2] + kGraspBeside[2]};
}

}  // namespace

SawyerTaskConfig LeverPull::Config() {
  SawyerTaskConfig config;
  config.id = "lever-pull";
  config.description = "Sawyer arm: pull a lever up to vertical";
  config.xml_file = "lever_pull.xml";
  config.hand_init = {0.0, 0.4, 0.2};
  config.obj_low = {-0.1, 0.7, 0.0};
  config.obj_high = {0.1, 0.8, 0.0};
  UseGoalOffset(kGoalOffset, config);
  return config;
}

LeverPull::LeverPull(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms LeverPull::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double tcp_to_grip = Distance(s.tcp, s.obj);
  const double angle_error = std::abs(joint_pos() - kUp);
  const double reach =
      LongTailTolerance(tcp_to_grip, 0.0, 0.04, Distance(s.tcp_init, handle_init()));
  const double engaged = HamacherProduct(reach, GripEffort(action));
  const double in_place = LongTailTolerance(angle_error, 0.0, kSuccess, kUp);
  RewardTerms terms = FixtureReward(engaged, in_place, angle_error <= kSuccess);
  terms.near_object = tcp_to_grip <= 0.05 ? 1.0 : 0.0;
  terms.grasp_success = s.touching_obj && action[3] > 0 ? 1.0 : 0.0;
  terms.obj_to_target = angle_error;
  return terms;
}

void LeverPullScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                  std::span<float> action) {
  const SawyerObs o(env_obs);
  const Vec3 axis_point{o.goal[0], o.goal[1], o.goal[2] - kArm};
  const Vec3 grasp = GraspPoint(o.obj1);
  // About +x the lever's angle reads pi at rest and pi/2 when up.
  GraspAndMove(o, grasp, NextPointOnArc(grasp, axis_point, 0, kUp), -1.0, action);
}

}  // namespace manyworlds::manipulation
