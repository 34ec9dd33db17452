// Tests of the articulated-fixture tasks (door, drawer, window, button,
// lever) beyond the suite-wide contract in sawyer_tasks_test.cc: the fixture
// follows the task state, the scripted policy solves nearly every variation
// and random actions almost none.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/manipulation/manipulation.h"
#include "manyworlds/manipulation/sawyer_task.h"

namespace manyworlds::manipulation {
namespace {

struct ArticulatedCase {
  std::string id;
  Vec3 goal_offset;   // goal - obj_pos
  Vec3 handle_start;  // handle (obs[4:7]) at reset - obj_pos
};

// The layouts documented in the task headers.
std::vector<ArticulatedCase> Cases() {
  // door-close starts open by 1.6 rad: the closed handle (0.3, -0.09) from
  // the hinge at obj_pos + (-0.1, -0.11), turned by -1.6 rad.
  const double c = std::cos(-1.6), s = std::sin(-1.6);
  const Vec3 door_close_start{-0.1 + 0.3 * c + 0.09 * s, -0.11 + 0.3 * s - 0.09 * c, 0.0};
  return {
      {"door-open", {-0.3, -0.45, 0.0}, {0.2, -0.2, 0.0}},
      {"drawer-open", {0.0, -0.36, 0.09}, {0.0, -0.16, 0.09}},
      {"drawer-close", {0.0, -0.16, 0.09}, {0.0, -0.36, 0.09}},
      {"button-press-topdown", {0.0, 0.0, -0.035}, {0.0, 0.0, 0.0}},
      {"window-open", {0.2, 0.0, 0.0}, {0.0, 0.0, 0.0}},
      {"window-close", {0.0, 0.0, 0.0}, {0.2, 0.0, 0.0}},
      {"door-close", {0.2, -0.2, 0.0}, door_close_start},
      {"lever-pull", {0.08, 0.0, 0.4}, {0.08, -0.2, 0.2}},
  };
}

Vec3 Param(const TaskState& state, const char* key) {
  const auto& v = state.params.at(key);
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

class ArticulatedTaskTest : public ::testing::TestWithParam<ArticulatedCase> {
 protected:
  void SetUp() override {
    RegisterManipulationSuite(registry_);
    env_ = registry_.Make(GetParam().id);
  }
  void TearDown() override {
    const auto& task = dynamic_cast<const SawyerTask&>(*env_);
    EXPECT_EQ(task.sim_warning_count(), 0) << task.last_sim_warning();
  }

  // Successful episodes (info "success" at any step) out of `variations`.
  int CountSuccesses(Policy& policy, int variations, uint64_t task_seed,
                     double* mean_steps = nullptr) {
    env_->SeedTask(task_seed);
    int successes = 0;
    long success_steps = 0;
    std::vector<float> action(4);
    for (int variation = 0; variation < variations; ++variation) {
      env_->ResetTaskState();
      Observation obs = env_->Reset();
      policy.BeginEpisode();
      for (int t = 0; t < kMaxEpisodeSteps; ++t) {
        policy.Act(obs.env_obs, obs.task_obs, action);
        StepResult r = env_->Step(action);
        if (r.info.Get("success") > 0) {
          ++successes;
          success_steps += t + 1;
          break;
        }
        obs = r.obs;
      }
    }
    if (mean_steps != nullptr) *mean_steps = successes ? double(success_steps) / successes : 0.0;
    return successes;
  }

  Registry registry_;
  std::unique_ptr<Env> env_;
};

TEST_P(ArticulatedTaskTest, GoalIsFixedRelativeToTheFixture) {
  env_->SeedTask(5);
  for (int i = 0; i < 20; ++i) {
    const TaskState state = env_->SampleTaskState();
    const Vec3 obj = Param(state, "obj_pos"), goal = Param(state, "goal_pos");
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(goal[k] - obj[k], GetParam().goal_offset[k], 1e-12);
  }
  TaskState moved = env_->SampleTaskState();
  moved.params["goal_pos"][2] = moved.params["goal_pos"][2].get<double>() + 0.01;
  EXPECT_THROW(env_->SetTaskState(moved), TaskStateError);
}

TEST_P(ArticulatedTaskTest, HandleStartsWhereTheTaskStatePutsTheFixture) {
  env_->SeedTask(6);
  for (int i = 0; i < 5; ++i) {
    env_->ResetTaskState();
    const Observation obs = env_->Reset();
    const Vec3 obj = Param(env_->GetTaskState(), "obj_pos");
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(obs.env_obs[kObsObj1Pos + k], obj[k] + GetParam().handle_start[k], 1e-5)
          << "axis " << k;
    }
  }
}

TEST_P(ArticulatedTaskTest, ScriptedPolicySolvesNearlyEveryVariation) {
  auto policy = MakeScriptedPolicy(GetParam().id);
  double mean_steps = 0;
  const int successes = CountSuccesses(*policy, 50, 99, &mean_steps);
  std::printf("%s: scripted %d/50, mean %.0f steps to success\n", GetParam().id.c_str(), successes,
              mean_steps);
  EXPECT_GE(successes, 45);
}

TEST_P(ArticulatedTaskTest, RandomActionsRarelySucceed) {
  RandomPolicy policy(env_->spec().action_space, 7);
  const auto start = std::chrono::steady_clock::now();
  const int successes = CountSuccesses(policy, 50, 98);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s: random %d/50 (%.0f steps/s)\n", GetParam().id.c_str(), successes,
              (50.0 * kMaxEpisodeSteps) / seconds);
  EXPECT_LE(successes, 5);
}

INSTANTIATE_TEST_SUITE_P(Fixtures, ArticulatedTaskTest, ::testing::ValuesIn(Cases()),
                         [](const auto& info) {
                           std::string name = info.param.id;
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

}  // namespace
}  // namespace manyworlds::manipulation
