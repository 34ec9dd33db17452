// Shared by the family tests (articulated fixtures, rotary, coffee, tool,
// peg, hole, container): a parameterised fixture that makes the case's task
// from the registry and fails the test if a step raised a MuJoCo warning,
// the variation's positions, the fixture checks of the tasks whose goal is
// fixed relative to a fixture, and the scripted- and random-policy checks
// every family runs (each prints its figure: the docs quote them).
#ifndef MANYWORLDS_TESTS_MANIPULATION_FAMILY_TEST_H_
#define MANYWORLDS_TESTS_MANIPULATION_FAMILY_TEST_H_

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/manipulation/episode_success.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/manipulation/manipulation.h"

namespace manyworlds::manipulation {

inline const std::string& CaseId(const std::string& id) { return id; }
template <typename Case>
const std::string& CaseId(const Case& c) {
  return c.id;
}

// Test names: the task id with '-' as '_'.
struct CaseName {
  template <typename Info>
  std::string operator()(const Info& info) const {
    std::string name = CaseId(info.param);
    for (char& c : name) c = c == '-' ? '_' : c;
    return name;
  }
};

template <typename Case>
class FamilyTest : public ::testing::TestWithParam<Case> {
 protected:
  void SetUp() override {
    RegisterManipulationSuite(registry_);
    env_ = registry_.Make(CaseId(this->GetParam()));
  }
  void TearDown() override {
    EXPECT_EQ(task().sim_warning_count(), 0) << task().last_sim_warning();
  }
  const std::string& id() const { return CaseId(this->GetParam()); }
  const SawyerTask& task() const { return dynamic_cast<const SawyerTask&>(*env_); }

  Registry registry_;
  std::unique_ptr<Env> env_;
};

// A task state's 3-vector parameter ("obj_pos", "goal_pos").
inline Vec3 Param(const TaskState& state, const char* key) {
  const auto& v = state.params.at(key);
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

// A fixture task's goal is obj_pos + goal_offset in 20 sampled task states
// (task seed 5), and a goal moved off it is rejected.
inline void ExpectGoalFixedRelativeToFixture(Env& env, const Vec3& goal_offset) {
  env.SeedTask(5);
  for (int i = 0; i < 20; ++i) {
    const TaskState state = env.SampleTaskState();
    const Vec3 obj = Param(state, "obj_pos"), goal = Param(state, "goal_pos");
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(goal[k] - obj[k], goal_offset[k], 1e-12);
  }
  TaskState moved = env.SampleTaskState();
  moved.params["goal_pos"][2] = moved.params["goal_pos"][2].get<double>() + 0.01;
  EXPECT_THROW(env.SetTaskState(moved), TaskStateError);
}

// After 5 resets (task seed 6), the object point (obs[4:7]) is at obj_pos +
// handle_start.
inline void ExpectHandleStartsAt(Env& env, const Vec3& handle_start) {
  env.SeedTask(6);
  for (int i = 0; i < 5; ++i) {
    env.ResetTaskState();
    const Observation obs = env.Reset();
    const Vec3 obj = Param(env.GetTaskState(), "obj_pos");
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(obs.env_obs[kObsObj1Pos + k], obj[k] + handle_start[k], 1e-5) << "axis " << k;
    }
  }
}

// The scripted policy over 50 variations (task seed 99).
inline void ExpectScriptedSolves(Env& env, const std::string& id, int at_least) {
  auto policy = MakeScriptedPolicy(id);
  double mean_steps = 0;
  const int successes = CountSuccesses(env, *policy, 50, 99, &mean_steps);
  std::printf("%s: scripted %d/50, mean %.0f steps to success\n", id.c_str(), successes,
              mean_steps);
  EXPECT_GE(successes, at_least) << id;
}

// Uniform random actions over 50 variations (task seed 98, policy seed 7).
inline void ExpectRandomRarelySolves(Env& env, const std::string& id, int at_most) {
  RandomPolicy policy(env.spec().action_space, 7);
  const auto start = std::chrono::steady_clock::now();
  const int successes = CountSuccesses(env, policy, 50, 98);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s: random %d/50 (%.0f steps/s)\n", id.c_str(), successes,
              (50.0 * kMaxEpisodeSteps) / seconds);
  EXPECT_LE(successes, at_most) << id;
}

// 20 sampled task states (task seed 8) survive a JSON round trip, lie in the
// task's ranges and keep object and goal >= min_obj_goal_xy apart in xy.
inline void ExpectSampledStatesRoundTripWithinRanges(Env& env, double min_obj_goal_xy) {
  env.SeedTask(8);
  const auto& config = dynamic_cast<const SawyerTask&>(env).config();
  for (int i = 0; i < 20; ++i) {
    const TaskState state = env.SampleTaskState();
    env.SetTaskState(TaskState::Parse(state.Dump()));
    EXPECT_EQ(env.GetTaskState(), state);
    const Vec3 obj = Param(state, "obj_pos"), goal = Param(state, "goal_pos");
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(obj[k], config.obj_low[k]);
      EXPECT_LE(obj[k], config.obj_high[k]);
      EXPECT_GE(goal[k], config.goal_low[k]);
      EXPECT_LE(goal[k], config.goal_high[k]);
    }
    EXPECT_GE(std::hypot(obj[0] - goal[0], obj[1] - goal[1]), min_obj_goal_xy);
  }
}

// In 5 scripted episodes (task seed 12), the object's height (obs[6]) at the
// first success lies in (above, below).
inline void ExpectObjectHeightAtSuccessBetween(Env& env, const std::string& id, double above,
                                               double below) {
  auto policy = MakeScriptedPolicy(id);
  env.SeedTask(12);
  std::vector<float> action(4);
  for (int variation = 0; variation < 5; ++variation) {
    env.ResetTaskState();
    Observation obs = env.Reset();
    for (int t = 0; t < kMaxEpisodeSteps; ++t) {
      policy->Act(obs.env_obs, obs.task_obs, action);
      StepResult r = env.Step(action);
      obs = r.obs;
      if (r.info.Get("success") > 0) {
        EXPECT_LT(obs.env_obs[kObsObj1Pos + 2], below) << id;
        EXPECT_GT(obs.env_obs[kObsObj1Pos + 2], above) << id;
        break;
      }
    }
  }
}

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_TESTS_MANIPULATION_FAMILY_TEST_H_
