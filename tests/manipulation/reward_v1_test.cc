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

TEST(RewardV1Test, ProgressIsV3sFormula) {
  EXPECT_NEAR(v1::Progress(0.3, 0.0), 1000 * 0.3 + 2000, 1e-9);
  const double d = 0.1;
  EXPECT_NEAR(v1::Progress(0.3, d),
              1000 * (0.3 - d) + 1000 * (std::exp(-d * d / 0.01) + std::exp(-d * d / 0.001)),
              1e-9);
  EXPECT_LT(v1::Progress(0.1, 1.0), 0.0);  // callers clamp where v3 does
}

TEST(RewardV1Test, ReachIsXyFirstThenPlainThenGrip) {
  SawyerState s;
  s.tcp = {0.0, 0.0, 0.3};
  s.tcp_init = {0.0, 0.0, 0.2};
  const Vec3 far{0.3, 0.4, 0.0};  // 0.5 away in the plane
  // xy-first: the planar distance plus the weighted height change since reset
  EXPECT_NEAR(v1::Reach(s, far, 1.0, 0.05, 2.0, 0.05), -0.5 - 2.0 * 0.1, 1e-12);
  // without xy-first: the distance
  EXPECT_NEAR(v1::Reach(s, far, 1.0, v1::kNoXyFirst, 2.0, 0.05), -std::hypot(0.5, 0.3), 1e-12);
  // within grip_radius: closing the fingers pays a[3] / 50
  const Vec3 near{0.0, 0.0, 0.27};
  EXPECT_NEAR(v1::Reach(s, near, 0.5, 0.05, 2.0, 0.05), -0.03 + 0.01, 1e-12);
  EXPECT_NEAR(v1::Reach(s, near, -0.5, 0.05, 2.0, 0.05), -0.03, 1e-12);
}

TEST(RewardV1Test, LiftBonusAndDropTest) {
  SawyerState s;
  s.v1_obj_height = 0.02;
  s.v1_height_target = 0.12;
  EXPECT_DOUBLE_EQ(v1::LiftBonus(s, 0.05, /*held=*/true, false), 100.0 * 0.12);
  EXPECT_DOUBLE_EQ(v1::LiftBonus(s, 0.05, false, /*near=*/true), 100.0 * 0.05);
  EXPECT_DOUBLE_EQ(v1::LiftBonus(s, 0.2, false, true), 100.0 * 0.12);  // capped at the target
  EXPECT_DOUBLE_EQ(v1::LiftBonus(s, 0.024, false, true), 0.0);  // not 5 mm up
  EXPECT_DOUBLE_EQ(v1::LiftBonus(s, 0.05, false, false), 0.0);
  EXPECT_DOUBLE_EQ(v1::LiftBonus(s, 0.05, true, false, /*floor=*/0.02), 100.0 * 0.1);
  EXPECT_TRUE(v1::Dropped(s, 0.024, 0.03, 0.03));
  EXPECT_FALSE(v1::Dropped(s, 0.026, 0.03, 0.03));  // 6 mm up
  EXPECT_FALSE(v1::Dropped(s, 0.024, 0.01, 0.03));  // at the goal
  EXPECT_FALSE(v1::Dropped(s, 0.024, 0.03, 0.01));  // in the hand
}

TEST(RewardV1Test, StepsReportTheV1RewardOfTheirStateRecord) {
  Registry registry;
  RegisterManipulationSuite(registry);
  for (const std::string& id : ManipulationTaskIds()) {
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

TEST(RewardV1Test, OnlyV1AndV2AreVersions) {
  Registry registry;
  RegisterManipulationSuite(registry);
  try {
    registry.Make("reach", {{"reward_version", "v3"}});
    ADD_FAILURE() << "reward_version=v3 accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("v1"), std::string::npos) << e.what();
  }
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
  auto mt50 = registry.Make("mt50", {{"reward_version", "v1"}, {"num_variations", 1}});
  const auto& all = dynamic_cast<const Benchmark&>(*mt50);
  ASSERT_EQ(all.num_tasks(), 50);
  for (int t = 0; t < all.num_tasks(); ++t) {
    EXPECT_EQ(all.member(t).reward_version(), RewardVersion::kV1) << all.task_name(t);
  }
}

}  // namespace
}  // namespace manyworlds::manipulation
