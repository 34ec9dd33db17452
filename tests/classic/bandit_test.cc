#include "manyworlds/classic/bandit.h"

#include <gtest/gtest.h>

#include <vector>

#include "manyworlds/core/error.h"
#include "tests/classic/test_util.h"

namespace manyworlds::classic::testing {
namespace {

const std::vector<double> kProbs = {0.1, 0.5, 0.9, 0.3, 0.9};

TaskState BanditTask(const std::vector<double>& probs) {
  return TaskState{"bandit", {{"probs", probs}}};
}

TEST(ClassicBanditTest, SampledProbabilitiesAreTheTaskObservation) {
  BanditEnv env(BanditEnv::Config{});
  env.SeedTask(4);
  env.ResetTaskState();
  const auto& probs = env.probs();
  ASSERT_EQ(probs.size(), 5u);
  for (size_t i = 0; i < probs.size(); ++i) {
    EXPECT_GE(probs[i], 0.0);
    EXPECT_LT(probs[i], 1.0);
    EXPECT_EQ(env.task_obs()[i], static_cast<float>(probs[i]));
  }
}

TEST(ClassicBanditTest, EmpiricalRewardFrequencyMatchesArmProbability) {
  BanditEnv env(BanditEnv::Config{});
  env.SetMaxEpisodeSteps(0);
  env.SetTaskState(BanditTask(kProbs));
  env.Seed(9);
  env.Reset();
  constexpr int kPulls = 20000;
  for (int arm = 0; arm < 5; ++arm) {
    int successes = 0;
    const float action[1] = {static_cast<float>(arm)};
    for (int i = 0; i < kPulls; ++i) successes += env.Step(action).reward == 1.0f ? 1 : 0;
    // 4.5 standard deviations of a frequency over 20000 pulls is <= 0.016.
    EXPECT_NEAR(static_cast<double>(successes) / kPulls, kProbs[arm], 0.016) << "arm " << arm;
  }
}

TEST(ClassicBanditTest, ObservationIsLastActionAndReward) {
  BanditEnv env(BanditEnv::Config{});
  env.SetTaskState(BanditTask({0.0, 1.0, 0.5, 0.5, 0.5}));
  Observation obs = env.Reset();
  EXPECT_EQ(obs.env_obs, std::vector<float>(6, 0.0f));
  const float pull_one[1] = {1.0f};
  StepResult r = env.Step(pull_one);
  EXPECT_EQ(r.reward, 1.0f);
  EXPECT_EQ(r.obs.env_obs, (std::vector<float>{0, 1, 0, 0, 0, 1}));
  const float pull_zero[1] = {0.0f};
  r = env.Step(pull_zero);
  EXPECT_EQ(r.reward, 0.0f);
  EXPECT_EQ(r.obs.env_obs, (std::vector<float>{1, 0, 0, 0, 0, 0}));
  EXPECT_EQ(env.Reset().env_obs, std::vector<float>(6, 0.0f));
}

TEST(ClassicBanditTest, InfoReportsRegretAndBestArm) {
  BanditEnv env(BanditEnv::Config{});
  env.SetTaskState(BanditTask(kProbs));
  env.Reset();
  const float worst[1] = {0.0f};
  StepResult r = env.Step(worst);
  EXPECT_FLOAT_EQ(r.info.Get("regret"), 0.8f);
  EXPECT_EQ(r.info.Get("best_arm"), 0.0f);
  // Arms 2 and 4 tie for best.
  for (float arm : {2.0f, 4.0f}) {
    const float best[1] = {arm};
    r = env.Step(best);
    EXPECT_EQ(r.info.Get("regret"), 0.0f);
    EXPECT_EQ(r.info.Get("best_arm"), 1.0f);
  }
}

TEST(ClassicBanditTest, NeverTerminatesAndTruncatesAtHorizon) {
  BanditEnv env(BanditEnv::Config{3, 20, false});
  env.Reset();
  const float action[1] = {0.0f};
  for (int i = 1; i <= 20; ++i) {
    StepResult r = env.Step(action);
    EXPECT_FALSE(r.terminated);
    EXPECT_EQ(r.truncated, i == 20);
  }
}

TEST(ClassicBanditTest, RejectsProbabilitiesOfTheWrongCountOrRange) {
  BanditEnv env(BanditEnv::Config{});
  EXPECT_THROW(env.SetTaskState(BanditTask({0.1, 0.2, 0.3})), TaskStateError);
  EXPECT_THROW(env.SetTaskState(BanditTask({0.1, 0.2, 0.3, 0.4, 1.5})), TaskStateError);
  EXPECT_THROW(env.SetTaskState(BanditTask({0.1, 0.2, 0.3, 0.4, -0.1})), TaskStateError);
  BanditEnv three(BanditEnv::Config{3, 10, false});
  EXPECT_THROW(three.SetTaskState(BanditTask(kProbs)), TaskStateError);
}

TEST(ClassicBanditTest, ConstructorValidatesOptions) {
  EXPECT_THROW(BanditEnv(BanditEnv::Config{1, 10, false}), ConfigError);
  EXPECT_THROW(BanditEnv(BanditEnv::Config{5, 0, false}), ConfigError);
}

}  // namespace
}  // namespace manyworlds::classic::testing
