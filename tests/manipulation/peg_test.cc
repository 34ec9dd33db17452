// Tests of the peg family (assembly, disassemble, peg-unplug-side) beyond
// the suite-wide contract in sawyer_tasks_test.cc: the objects start where
// Meta-World v3's do relative to the task state, the record holds what v3's
// reward reads, task states round-trip and bad ones are rejected, the
// scripted policy solves nearly every variation and random actions almost
// none.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/manipulation.h"
#include "manyworlds/manipulation/sawyer_task.h"
#include "tests/manipulation/family_test.h"

namespace manyworlds::manipulation {
namespace {

struct PegCase {
  std::string id;
  Vec3 object_point;     // obs[4:7] at reset - obj_pos
  Vec3 obj_init;         // the record's obj_init - obj_pos (v3's obj_init_pos)
  std::vector<float> quat;  // obs[7:11] at reset, v3's (w, x, y, z)
  int min_scripted;      // of 50
  int max_random;        // of 50
};

// Measured in the official package at reset (its object point and
// obj_init_pos relative to the variation's object position; obs[7:11]).
std::vector<PegCase> Cases() {
  return {
      // The nut lies on the table at reset, its handle's centre 0.019 m up
      // (obj_pos z is 0.02 or 0.025; v3 drops it from there, to 0.0189).
      {"assembly", {0.13, 0.0, -0.001}, {0, 0, 0}, {0.7071f, 0.0f, 0.0f, 0.7071f}, 48, 2},
      {"disassemble", {0.13, 0.0, -0.006}, {0, 0, 0}, {0.7071f, 0.0f, 0.0f, 0.7071f}, 48, 2},
      // v3's obj_init_pos is the plug's end at reset.
      {"peg-unplug-side", {0.084, 0.0, 0.131}, {0.084, 0.0, 0.131}, {1.0f, 0.0f, 0.0f, 0.0f}, 48, 6},
  };
}

void PrintTo(const PegCase& c, std::ostream* os) { *os << c.id; }


using PegTaskTest = FamilyTest<PegCase>;

TEST_P(PegTaskTest, ObjectStartsWhereTheTaskStatePutsIt) {
  env_->SeedTask(6);
  for (int i = 0; i < 5; ++i) {
    env_->ResetTaskState();
    const Observation obs = env_->Reset();
    const Vec3 obj = Param(env_->GetTaskState(), "obj_pos");
    const SawyerState& s = dynamic_cast<const SawyerTask&>(*env_).state();
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(obs.env_obs[kObsObj1Pos + k], obj[k] + GetParam().object_point[k], 2e-3)
          << "axis " << k;
      EXPECT_NEAR(s.obj_init[k], obj[k] + GetParam().obj_init[k], 1e-9) << "axis " << k;
    }
    for (int k = 0; k < 4; ++k) {
      EXPECT_NEAR(obs.env_obs[kObsObj1Quat + k], GetParam().quat[k], 2e-3) << "quat " << k;
      EXPECT_EQ(static_cast<float>(s.obj_quat[k]), obs.env_obs[kObsObj1Quat + k]) << "quat " << k;
    }
  }
}

TEST_P(PegTaskTest, TaskStatesRoundTripAndBadOnesAreRejected) {
  env_->SeedTask(8);
  for (int i = 0; i < 10; ++i) {
    const TaskState state = env_->SampleTaskState();
    env_->SetTaskState(state);
    EXPECT_EQ(env_->GetTaskState().params, state.params);
    const TaskState back = TaskState::FromJson(state.ToJson());
    env_->SetTaskState(back);
    EXPECT_EQ(env_->GetTaskState().params, state.params);
  }
  TaskState moved = env_->SampleTaskState();
  moved.params["goal_pos"][2] = moved.params["goal_pos"][2].get<double>() + 0.02;
  EXPECT_THROW(env_->SetTaskState(moved), TaskStateError);
  TaskState outside = env_->SampleTaskState();
  outside.params["obj_pos"][1] = 2.0;
  EXPECT_THROW(env_->SetTaskState(outside), TaskStateError);
  TaskState short_vector = env_->SampleTaskState();
  short_vector.params["obj_pos"] = {0.0, 0.6};
  EXPECT_THROW(env_->SetTaskState(short_vector), TaskStateError);
}

TEST_P(PegTaskTest, ScriptedPolicySolvesNearlyEveryVariation) {
  ExpectScriptedSolves(*env_, id(), GetParam().min_scripted);
}

TEST_P(PegTaskTest, RandomActionsRarelySucceed) {
  ExpectRandomRarelySolves(*env_, id(), GetParam().max_random);
}

INSTANTIATE_TEST_SUITE_P(Peg, PegTaskTest, ::testing::ValuesIn(Cases()),
                         CaseName());

}  // namespace
}  // namespace manyworlds::manipulation
