// The classical bandit strategies against closed forms and each other on
// the RL2 paper's setting (5 arms drawn U[0, 1], trials of 10 pulls).
#include "manyworlds/classic/bandit_baselines.h"

#include <gtest/gtest.h>

#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"

namespace manyworlds::classic {
namespace {

std::vector<std::vector<double>> UniformTasks(int64_t count, int64_t arms, uint64_t seed) {
  Rng rng(seed);
  std::vector<std::vector<double>> tasks(count, std::vector<double>(arms));
  for (auto& t : tasks) {
    for (double& p : t) p = rng.Uniform();
  }
  return tasks;
}

TEST(BanditBaselinesTest, RandomMatchesItsExpectationAndTheOthersBeatIt) {
  const auto tasks = UniformTasks(2000, 5, 3);
  const BaselineResult random = RunBanditBaseline("random", tasks, 10, 5, 1);
  // E = 10 x mean arm probability = 5.0; 10,000 trials: standard error ~0.02
  EXPECT_NEAR(random.mean_trial_return, 5.0, 0.1);
  EXPECT_LT(random.standard_error, 0.05);
  for (const char* name : {"greedy", "ucb1", "thompson"}) {
    const BaselineResult r = RunBanditBaseline(name, tasks, 10, 5, 1);
    EXPECT_GT(r.mean_trial_return, random.mean_trial_return + 0.4) << name;
    EXPECT_LT(r.mean_trial_return, 10.0 * 5.0 / 6.0) << name;  // E[max of 5 U(0, 1)] per pull
  }
}

TEST(BanditBaselinesTest, AnObviousBestArmIsFoundAndBadInputIsRefused) {
  const std::vector<std::vector<double>> sure = {{0.0, 1.0, 0.0}};
  // greedy: arm 0 (pays 0), arm 1 (pays), then arm 1 for good
  EXPECT_DOUBLE_EQ(RunBanditBaseline("greedy", sure, 20, 3, 1).mean_trial_return, 19.0);
  // UCB1 keeps revisiting the losing arms as ln t grows (14, as a
  // hand-written UCB1 in Python also gives)
  EXPECT_DOUBLE_EQ(RunBanditBaseline("ucb1", sure, 20, 3, 1).mean_trial_return, 14.0);
  EXPECT_THROW(RunBanditBaseline("gittins", sure, 10, 1, 1), ConfigError);
  EXPECT_THROW(RunBanditBaseline("ucb1", {{0.5, 1.5}}, 10, 1, 1), ConfigError);
  EXPECT_THROW(RunBanditBaseline("ucb1", {{0.5, 0.5}, {0.5}}, 10, 1, 1), ConfigError);
}

}  // namespace
}  // namespace manyworlds::classic
