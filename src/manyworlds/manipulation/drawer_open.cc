#include "manyworlds/manipulation/drawer_open.h"

namespace manyworlds::manipulation {
namespace {

// The closed handle is at obj_pos + (0, -0.16, 0.09) (drawer_fixture.xml).
constexpr Vec3 kGoalOffset{0.0, -0.36, 0.09};
constexpr double kSuccess = 0.03;
// Pads at +-0.04 m while descending: the drawer face is 0.06 m behind the bar.
constexpr double kApproachGrip = -0.5;

FixtureSpec Fixture() { return {"drawer_case", {}, "drawer_slide", 0.0, kGoalOffset}; }

}  // namespace

SawyerTaskConfig DrawerOpen::Config() {
  SawyerTaskConfig config;
  config.id = "drawer-open";
  config.description = "Sawyer arm: pull a drawer open by its handle";
  config.xml_file = "drawer_open.xml";
  config.hand_init = {0.0, 0.6, 0.2};
  config.obj_low = {-0.1, 0.9, 0.0};
  config.obj_high = {0.1, 0.9, 0.0};
  UseGoalOffset(kGoalOffset, config);
  return config;
}

DrawerOpen::DrawerOpen(SawyerOptions options) : ArticulatedTask(Config(), Fixture(), options) {}

RewardTerms DrawerOpen::ComputeReward(const SawyerState& s, std::span<const float> action) const {
  const double tcp_to_handle = Distance(s.tcp, s.obj);
  const double obj_to_target = Distance(s.obj, s.goal);
  const double reach =
      LongTailTolerance(tcp_to_handle, 0.0, 0.02, Distance(s.tcp_init, handle_init()));
  const double engaged = HamacherProduct(reach, GripEffort(action));
  const double in_place =
      LongTailTolerance(obj_to_target, 0.0, kSuccess, Distance(handle_init(), s.goal));
  RewardTerms terms = FixtureReward(engaged, in_place, obj_to_target <= kSuccess);
  terms.near_object = tcp_to_handle <= 0.03 ? 1.0 : 0.0;
  terms.grasp_success = s.touching_obj && action[3] > 0 ? 1.0 : 0.0;
  terms.obj_to_target = obj_to_target;
  return terms;
}

void DrawerOpenScriptedPolicy::Act(std::span<const float> env_obs, std::span<const float>,
                                   std::span<float> action) {
  const SawyerObs o(env_obs);
  // Aim 1 cm past the goal so the pull does not stall just short of it.
  GraspAndMove(o, o.obj1, {o.goal[0], o.goal[1] - 0.01, o.goal[2]}, kApproachGrip, action);
}

}  // namespace manyworlds::manipulation
