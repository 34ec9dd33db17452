// Reward version v1: the option, the reset-time fields, the shared pieces,
// and steps that report what EvaluateReward computes on the state record.
// (Agreement with Meta-World's own v1 is python/tests/test_metaworld_fidelity_v1.py.)
#include "manyworlds/manipulation/reward_v1.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"
#include "manyworlds/manipulation/benchmark.h"
#include "manyworlds/manipulation/manipulation.h"

namespace manyworlds::manipulation {
namespace {

std::vector<std::string> TasksWithV1() {
  std::vector<std::string> ids;
  for (const auto& id : ManipulationTaskIds()) {
    if (MakeSawyerTask(id)->HasRewardV1()) ids.push_back(id);
  }
  return ids;
}

TEST(RewardV1Test, ProgressIsV3sFormula) {
  EXPECT_NEAR(v1::Progress(0.3, 0.0), 1000 * 0.3 + 2000, 1e-9);
  const double d = 0.1;
  EXPECT_NEAR(v1::Progress(0.3, d),
              1000 * (0.3 - d) + 1000 * (std::exp(-d * d / 0.01) + std::exp(-d * d / 0.001)),
              1e-9);
  EXPECT_LT(v1::Progress(0.1, 1.0), 0.0);  // callers clamp where v3 does
}

TEST(RewardV1Test, TheMt10TasksHaveIt) {
  const std::vector<std::string> ids = TasksWithV1();
  for (const char* task : {"reach", "push", "pick-place", "door-open", "drawer-open",
                           "drawer-close", "button-press-topdown", "peg-insert-side",
                           "window-open", "window-close"}) {
    EXPECT_NE(std::find(ids.begin(), ids.end(), task), ids.end()) << task;
  }
}

TEST(RewardV1Test, StepsReportTheV1RewardOfTheirStateRecord) {
  Registry registry;
  RegisterManipulationSuite(registry);
  for (const std::string& id : TasksWithV1()) {
    auto env = registry.Make(id, {{"reward_version", "v1"}});
    auto* task = dynamic_cast<SawyerTask*>(env.get());
    ASSERT_NE(task, nullptr) << id;
    EXPECT_EQ(task->reward_version(), RewardVersion::kV1);
    env->SeedTask(3);
    env->ResetTaskState();
    env->Reset();
    // (button-press-wall's is 0, as v3's: it compares the button's and the goal's heights)
    if (id != "button-press-wall") {
      EXPECT_GT(task->state().v1_max_dist, 0.0) << id << ": the normaliser is set at reset";
    }
    const std::vector<float> action{0.3f, 0.5f, -0.2f, 0.4f};
    double largest = 0;
    for (int t = 0; t < 20; ++t) {
      const StepResult r = env->Step(action);
      const RewardTerms terms = task->EvaluateReward(task->state(), action);
      EXPECT_FLOAT_EQ(r.reward, static_cast<float>(terms.reward)) << id;
      largest = std::max(largest, std::abs(terms.reward));
    }
    // v1's rewards are not v2's: v2 lies in [0, 10] and has no negative reach term
    auto v2 = MakeSawyerTask(id);
    v2->SeedTask(3);
    v2->ResetTaskState();
    v2->Reset();
    const StepResult r2 = v2->Step(action);
    const RewardTerms v2_terms = v2->EvaluateReward(v2->state(), action);
    EXPECT_FLOAT_EQ(r2.reward, static_cast<float>(v2_terms.reward)) << id;
    EXPECT_NE(task->EvaluateReward(v2->state(), action).reward, v2_terms.reward) << id;
  }
}

TEST(RewardV1Test, TasksWithoutItRefuseTheOption) {
  Registry registry;
  RegisterManipulationSuite(registry);
  const std::vector<std::string> with = TasksWithV1();
  for (const auto& id : ManipulationTaskIds()) {
    if (std::find(with.begin(), with.end(), id) != with.end()) continue;
    try {
      registry.Make(id, {{"reward_version", "v1"}});
      ADD_FAILURE() << id << " accepted reward_version=v1";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("reward_version=v1 is not available"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(registry.Make("reach", {{"reward_version", "v3"}}), ConfigError);
}

TEST(RewardV1Test, BenchmarksPassTheVersionToEveryMember) {
  Registry registry;
  RegisterManipulationSuite(registry);
  auto mt10 = registry.Make("mt10", {{"reward_version", "v1"}, {"num_variations", 2}});
  const auto& bench = dynamic_cast<const Benchmark&>(*mt10);
  for (int t = 0; t < bench.num_tasks(); ++t) {
    EXPECT_EQ(bench.member(t).reward_version(), RewardVersion::kV1) << bench.task_name(t);
  }
  auto ml1 = registry.Make("ml1", {{"task", "push"}, {"reward_version", "v1"}});
  EXPECT_EQ(dynamic_cast<const Benchmark&>(*ml1).member(0).reward_version(), RewardVersion::kV1);
  EXPECT_EQ(dynamic_cast<const Benchmark&>(*registry.Make("mt10")).member(0).reward_version(),
            RewardVersion::kV2);
  try {
    registry.Make("mt50", {{"reward_version", "v1"}, {"num_variations", 1}});
    ADD_FAILURE() << "mt50 accepted v1 although some members lack it";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("reward_version=v1 is not available"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace manyworlds::manipulation
