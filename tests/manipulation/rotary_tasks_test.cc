// Tests of the rotary tasks (faucet-open, faucet-close, dial-turn,
// door-lock, door-unlock) beyond the suite-wide contract in
// sawyer_tasks_test.cc: the fixture follows the task state, the object point
// starts where Meta-World v3's does, the record holds what v3's reward reads,
// the scripted policy solves nearly every variation and random actions
// almost none.
#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "manyworlds/manipulation/sawyer_task.h"
#include "tests/manipulation/family_test.h"

namespace manyworlds::manipulation {
namespace {

struct RotaryCase {
  std::string id;
  Vec3 goal_offset;   // goal - obj_pos
  Vec3 handle_start;  // the object point (obs[4:7]) at reset - obj_pos
  Vec3 handle_init;   // the record's handle_init - the object point at reset
  Vec3 obj_init{};    // the record's obj_init - obj_pos
};

// Meta-World v3's layouts, measured in the official package (its
// _target_pos and object point at reset relative to its obj_init_pos; for
// dial-turn its dial_push_position).
std::vector<RotaryCase> Cases() {
  return {
      {"faucet-open", {0.175, 0.0, 0.125}, {-0.015, -0.175, 0.114}, {0, 0, 0}},
      {"faucet-close", {-0.175, 0.0, 0.125}, {0.015, -0.175, 0.114}, {0, 0, 0}},
      {"dial-turn", {0.0, 0.03, 0.03}, {0.0, -0.05, 0.0}, {0.05, 0.02, 0.09}},
      // v3's obj_init_pos here is the lock's axis point.
      {"door-lock", {0.0, -0.158, -0.039}, {0.09, -0.158, 0.071}, {0, 0, 0}, {0.0, -0.118, 0.061}},
      {"door-unlock", {0.1, -0.158, 0.061}, {-0.01, -0.158, -0.029}, {0, 0, 0},
       {0.0, -0.118, 0.061}},
  };
}

void PrintTo(const RotaryCase& c, std::ostream* os) { *os << c.id; }

using RotaryTaskTest = FamilyTest<RotaryCase>;

TEST_P(RotaryTaskTest, GoalIsFixedRelativeToTheFixture) {
  ExpectGoalFixedRelativeToFixture(*env_, GetParam().goal_offset);
}

TEST_P(RotaryTaskTest, HandleStartsWhereTheTaskStatePutsTheFixture) {
  ExpectHandleStartsAt(*env_, GetParam().handle_start);
}

TEST_P(RotaryTaskTest, RecordHoldsTheFixtureQuantitiesMetaWorldReads) {
  env_->SeedTask(6);
  env_->ResetTaskState();
  const Observation obs = env_->Reset();
  const SawyerState& s = task().state();
  const Vec3 obj = Param(env_->GetTaskState(), "obj_pos");
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(s.handle_init[k], s.obj[k] + GetParam().handle_init[k], 1e-12);
    EXPECT_NEAR(s.obj_init[k], obj[k] + GetParam().obj_init[k], 1e-12);  // v3's obj_init_pos
  }
  // obs[7:11]: the fixture base's (w, x, y, z), upright, as v3 reads it,
  // however far the knob has turned.
  const std::vector<float> upright{1.0f, 0.0f, 0.0f, 0.0f};
  const std::vector<float> quat(obs.env_obs.begin() + kObsObj1Quat,
                                obs.env_obs.begin() + kObsObj1Quat + 4);
  EXPECT_EQ(quat, upright);
}

TEST_P(RotaryTaskTest, ScriptedPolicySolvesNearlyEveryVariation) {
  ExpectScriptedSolves(*env_, id(), 45);
}

TEST_P(RotaryTaskTest, RandomActionsRarelySucceed) {
  ExpectRandomRarelySolves(*env_, id(), 5);
}

INSTANTIATE_TEST_SUITE_P(Knobs, RotaryTaskTest, ::testing::ValuesIn(Cases()), CaseName());

}  // namespace
}  // namespace manyworlds::manipulation
