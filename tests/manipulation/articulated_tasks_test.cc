// Tests of the articulated-fixture tasks (door, drawer, window, button,
// lever) beyond the suite-wide contract in sawyer_tasks_test.cc: the fixture
// follows the task state, the scripted policy solves nearly every variation
// and random actions almost none.
#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "manyworlds/manipulation/sawyer_task.h"
#include "tests/manipulation/family_test.h"

namespace manyworlds::manipulation {
namespace {

struct ArticulatedCase {
  std::string id;
  Vec3 goal_offset;   // goal - obj_pos
  Vec3 handle_start;  // the object point (obs[4:7]) at reset - obj_pos
  double joint_qpos_start;  // the record's joint_qpos at reset
  // Random-action successes allowed of 50. handle-press: v3's handle sits
  // right under the hand's start, and v3's own random policy presses it in
  // 12 of 50 episodes (measured); ours 6.
  int max_random = 5;
};

// The layouts documented in the task headers: Meta-World v3's, measured in
// the official package (its _target_pos and object point at reset, relative
// to its obj_init_pos).
std::vector<ArticulatedCase> Cases() {
  // door-close starts open by pi/2: the closed handle (0.3757, -0.1071) from
  // the hinge at obj_pos + (-0.185, -0.1), turned by -1.5708 rad.
  const double c = std::cos(-1.5708), s = std::sin(-1.5708);
  const Vec3 door_close_start{-0.185 + 0.3757 * c + 0.1071 * s, -0.1 + 0.3757 * s - 0.1071 * c,
                              0.0};
  return {
      {"door-open", {-0.3, -0.45, 0.0}, {0.1907, -0.2071, 0.0}, 0.0},
      {"drawer-open", {0.0, -0.36, 0.09}, {0.0, -0.17, 0.09}, 0.0},
      {"drawer-close", {0.0, -0.16, 0.09}, {0.0, -0.32, 0.14}, 0.0},
      {"button-press-topdown", {0.0, 0.0, 0.1}, {0.0, 0.0, 0.1935}, 0.0},
      {"window-open", {0.2, 0.0, 0.0}, {-0.04, -0.095, 0.0}, 0.0},
      {"window-close", {0.0, 0.0, 0.0}, {0.21, -0.095, 0.0}, 0.0},
      {"door-close", {0.2, -0.2, 0.0}, door_close_start, -1.5708},
      {"lever-pull", {0.12, 0.0, 0.45}, {0.12, -0.2, 0.25}, 0.0},
      {"button-press", {0.0, -0.1, 0.0}, {0.0, -0.193, 0.0}, 0.0},
      {"button-press-wall", {0.0, -0.1, 0.0}, {0.0, -0.193, 0.0}, 0.0},
      {"button-press-topdown-wall", {0.0, 0.0, 0.1}, {0.0, 0.0, 0.1935}, 0.0},
      {"handle-press", {0.0, -0.216, 0.075}, {0.0, -0.216, 0.171}, 0.0, 10},
      {"handle-press-side", {0.216, 0.0, 0.075}, {0.216, 0.0, 0.171}, 0.0},
      {"handle-pull", {0.0, -0.216, 0.172}, {0.05, -0.216, 0.064}, 0.0},
      {"handle-pull-side", {0.216, 0.0, 0.172}, {0.17, 0.0, 0.05}, 0.0},
  };
}

void PrintTo(const ArticulatedCase& c, std::ostream* os) { *os << c.id; }

using ArticulatedTaskTest = FamilyTest<ArticulatedCase>;

TEST_P(ArticulatedTaskTest, GoalIsFixedRelativeToTheFixture) {
  ExpectGoalFixedRelativeToFixture(*env_, GetParam().goal_offset);
}

TEST_P(ArticulatedTaskTest, HandleStartsWhereTheTaskStatePutsTheFixture) {
  ExpectHandleStartsAt(*env_, GetParam().handle_start);
}

TEST_P(ArticulatedTaskTest, RecordHoldsTheFixtureQuantitiesMetaWorldReads) {
  env_->SeedTask(6);
  env_->ResetTaskState();
  const Observation obs = env_->Reset();
  const SawyerState& s = task().state();
  const Vec3 obj = Param(env_->GetTaskState(), "obj_pos");
  EXPECT_NEAR(s.joint_qpos, GetParam().joint_qpos_start, 1e-3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(s.handle_init[k], s.obj[k]);  // the object point at reset
    // v3's obj_init_pos: the object point in drawer-close and
    // handle-pull-side, obj_pos elsewhere.
    const bool at_point = GetParam().id == "drawer-close" || GetParam().id == "handle-pull-side";
    EXPECT_EQ(s.obj_init[k], at_point ? s.obj[k] : obj[k]);
  }
  EXPECT_NEAR(s.obj_to_target_init, GetParam().id.starts_with("button-press") ? 0.0935 : 0.0, 1e-4);
  // obs[7:11]: (w, x, y, z) of an upright body in drawer-open and the
  // button tasks, zeros in drawer-close and the windows.
  const std::vector<float> quat(obs.env_obs.begin() + kObsObj1Quat,
                                obs.env_obs.begin() + kObsObj1Quat + 4);
  const std::string& id = GetParam().id;
  if (id == "drawer-open" || id.starts_with("button-press")) {
    EXPECT_NEAR(quat[0], 1.0f, 1e-4);
  } else if (id == "drawer-close" || id == "window-open" || id == "window-close" ||
             id.starts_with("handle-")) {
    EXPECT_EQ(quat, std::vector<float>(4, 0.0f));
  }
}

TEST_P(ArticulatedTaskTest, ScriptedPolicySolvesNearlyEveryVariation) {
  ExpectScriptedSolves(*env_, id(), 45);
}

TEST_P(ArticulatedTaskTest, RandomActionsRarelySucceed) {
  ExpectRandomRarelySolves(*env_, id(), GetParam().max_random);
}

INSTANTIATE_TEST_SUITE_P(Fixtures, ArticulatedTaskTest, ::testing::ValuesIn(Cases()), CaseName());

}  // namespace
}  // namespace manyworlds::manipulation
