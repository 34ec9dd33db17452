// Tests of the coffee tasks (coffee-button, coffee-push, coffee-pull)
// beyond the suite-wide contract in sawyer_tasks_test.cc: the machine and
// the mug stand where Meta-World v3 puts them, the record holds what v3's
// reward reads, task states are checked, the scripted policy solves nearly
// every variation and random actions almost none.
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

// The mug's foot at rest (v3's settled height, measured) and v3's yaw at
// reset, as the quaternion's z.
constexpr double kMugRestZ = -0.0028118;
constexpr double kMugYawQuatZ = -0.02984;


Vec3 BodyPos(const SawyerTask& task, const char* name) {
  const int body = mj_name2id(task.model(), mjOBJ_BODY, name);
  EXPECT_GE(body, 0) << name;
  const mjtNum* p = task.data()->xpos + 3 * body;
  return {p[0], p[1], p[2]};
}

using CoffeeTest = FamilyTest<std::string>;

TEST_P(CoffeeTest, ScriptedPolicySolvesNearlyEveryVariation) {
  ExpectScriptedSolves(*env_, id(), 48);
}

TEST_P(CoffeeTest, RandomActionsRarelySucceed) {
  ExpectRandomRarelySolves(*env_, id(), 5);
}

TEST_P(CoffeeTest, TaskStatesRoundTripAndBadOnesAreRejected) {
  env_->SeedTask(4);
  for (int i = 0; i < 20; ++i) {
    const TaskState state = env_->SampleTaskState();
    env_->SetTaskState(TaskState::Parse(state.Dump()));
    EXPECT_EQ(env_->GetTaskState(), state);
  }
  const TaskState state = env_->SampleTaskState();
  TaskState bad = state;
  bad.params["obj_pos"][2] = 0.002;  // v3's heights lie in [-0.001, 0.001]
  EXPECT_THROW(env_->SetTaskState(bad), TaskStateError);
  bad = state;
  bad.params["goal_pos"] = {0.0, 0.7};
  EXPECT_THROW(env_->SetTaskState(bad), TaskStateError);
}

INSTANTIATE_TEST_SUITE_P(Coffee, CoffeeTest,
                         ::testing::Values("coffee-button", "coffee-push", "coffee-pull"),
                         CaseName());

class CoffeeButtonTest : public CoffeeTest {};

TEST_P(CoffeeButtonTest, ButtonAndMugStandWhereMetaWorldPutsThem) {
  env_->SeedTask(6);
  for (int i = 0; i < 5; ++i) {
    const TaskState state = env_->SampleTaskState();
    const Vec3 obj = Param(state, "obj_pos"), goal = Param(state, "goal_pos");
    // v3's _target_pos: the button's face pressed in by its full 3 cm.
    EXPECT_NEAR(goal[0] - obj[0], 0.0, 1e-12);
    EXPECT_NEAR(goal[1] - obj[1], -0.19, 1e-12);
    EXPECT_NEAR(goal[2] - obj[2], 0.3, 1e-12);
    env_->SetTaskState(state);
    const Observation obs = env_->Reset();
    // v3's buttonStart site and its literal (1, 0, 0, 0).
    const std::vector<float> face{static_cast<float>(obj[0]), static_cast<float>(obj[1] - 0.22),
                                  static_cast<float>(obj[2] + 0.3)};
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(obs.env_obs[kObsObj1Pos + k], face[k], 1e-6);
    EXPECT_EQ(std::vector<float>(obs.env_obs.begin() + kObsObj1Quat,
                                 obs.env_obs.begin() + kObsObj1Quat + 4),
              (std::vector<float>{1.0f, 0.0f, 0.0f, 0.0f}));
    const Vec3 mug = BodyPos(task(), "mug");
    EXPECT_NEAR(mug[0], obj[0], 1e-12);
    EXPECT_NEAR(mug[1], obj[1] - 0.22, 1e-12);
    EXPECT_NEAR(mug[2], kMugRestZ, 1e-12);
    // The record: v3's obj_init_pos is the machine, its press margin max_dist.
    const SawyerState& s = task().state();
    for (int k = 0; k < 3; ++k) EXPECT_EQ(s.obj_init[k], obj[k]);
    EXPECT_EQ(s.obj_to_target_init, 0.03);
  }
  TaskState moved = env_->SampleTaskState();
  moved.params["goal_pos"][1] = moved.params["goal_pos"][1].get<double>() + 0.01;
  EXPECT_THROW(env_->SetTaskState(moved), TaskStateError);
}

INSTANTIATE_TEST_SUITE_P(Coffee, CoffeeButtonTest, ::testing::Values("coffee-button"),
                         [](const auto&) { return std::string("coffee_button"); });

class CoffeeMugTest : public CoffeeTest {};

TEST_P(CoffeeMugTest, MachineAndMugStandWhereMetaWorldPutsThem) {
  const bool push = GetParam() == "coffee-push";
  env_->SeedTask(8);
  for (int i = 0; i < 5; ++i) {
    env_->ResetTaskState();
    const Observation obs = env_->Reset();
    const Vec3 obj = Param(env_->GetTaskState(), "obj_pos");
    const Vec3 goal = Param(env_->GetTaskState(), "goal_pos");
    EXPECT_GE(std::hypot(obj[0] - goal[0], obj[1] - goal[1]), 0.15);
    // The machine behind the goal (push) or the mug's start (pull).
    const Vec3& at_machine = push ? goal : obj;
    const Vec3 machine = BodyPos(task(), "coffee_machine");
    EXPECT_NEAR(machine[0], at_machine[0], 1e-12);
    EXPECT_NEAR(machine[1], at_machine[1] + 0.22, 1e-12);
    // The mug's foot at rest with v3's yaw; obs[7:11] its (x, y, z, w).
    EXPECT_NEAR(obs.env_obs[kObsObj1Pos + 0], obj[0], 1e-6);
    EXPECT_NEAR(obs.env_obs[kObsObj1Pos + 1], obj[1], 1e-6);
    EXPECT_NEAR(obs.env_obs[kObsObj1Pos + 2], kMugRestZ, 1e-6);
    EXPECT_NEAR(obs.env_obs[kObsObj1Quat + 2], kMugYawQuatZ, 1e-6);
    EXPECT_NEAR(obs.env_obs[kObsObj1Quat + 3], std::sqrt(1 - kMugYawQuatZ * kMugYawQuatZ), 1e-6);
    // v3's obj_init_pos is the drawn start, height included.
    for (int k = 0; k < 3; ++k) EXPECT_EQ(task().state().obj_init[k], obj[k]);
  }
}

TEST_P(CoffeeMugTest, GraspSuccessStaysZeroAsInMetaWorld) {
  // v3's main object is the mug's visual mesh, which nothing touches.
  auto policy = MakeScriptedPolicy(GetParam());
  env_->SeedTask(3);
  env_->ResetTaskState();
  Observation obs = env_->Reset();
  std::vector<float> action(4);
  bool held = false;
  for (int t = 0; t < 150; ++t) {
    policy->Act(obs.env_obs, obs.task_obs, action);
    const StepResult r = env_->Step(action);
    EXPECT_EQ(r.info.Get("grasp_success"), 0.0f);
    held = held || r.info.Get("near_object") > 0;
    obs = r.obs;
  }
  EXPECT_TRUE(held);
}

INSTANTIATE_TEST_SUITE_P(Coffee, CoffeeMugTest, ::testing::Values("coffee-push", "coffee-pull"),
                         CaseName());

}  // namespace
}  // namespace manyworlds::manipulation
