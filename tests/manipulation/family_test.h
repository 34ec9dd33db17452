// Shared by the family tests (coffee, tool, peg, hole, container): a
// parameterised fixture that makes the case's task from the registry and
// fails the test if a step raised a MuJoCo warning, the variation's
// positions, and the scripted- and random-policy checks every family runs
// (each prints its figure: the docs quote them).
#ifndef MANYWORLDS_TESTS_MANIPULATION_FAMILY_TEST_H_
#define MANYWORLDS_TESTS_MANIPULATION_FAMILY_TEST_H_

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "tests/manipulation/episode_success.h"
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

}  // namespace manyworlds::manipulation

#endif  // MANYWORLDS_TESTS_MANIPULATION_FAMILY_TEST_H_
