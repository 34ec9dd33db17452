// The tabular-MDP strategies against closed forms, each other and the env
// they stand beside (10 states, 5 actions, episodes of 10 steps, trials of
// 10 episodes: the RL2 paper's setting on the env's task distribution).
#include "manyworlds/classic/tabular_mdp_baselines.h"

#include <gtest/gtest.h>

#include <vector>

#include "manyworlds/classic/tabular_mdp.h"
#include "manyworlds/core/error.h"

namespace manyworlds::classic {
namespace {

// MDPs drawn by the env's own task generator.
std::vector<TabularMdp> EnvTasks(int64_t count, int64_t states, int64_t actions, uint64_t seed) {
  TabularMdpEnv env(TabularMdpEnv::Config{states, actions, 10, false});
  env.SeedTask(seed);
  std::vector<TabularMdp> tasks;
  for (int64_t i = 0; i < count; ++i) {
    env.ResetTaskState();
    TabularMdp m{states, actions, {}, {}};
    for (int64_t s = 0; s < states; ++s) {
      for (int64_t a = 0; a < actions; ++a) {
        m.rewards.push_back(env.reward_mean(s, a));
        for (int64_t n = 0; n < states; ++n) m.transitions.push_back(env.transition(s, a, n));
      }
    }
    tasks.push_back(std::move(m));
  }
  return tasks;
}

TEST(TabularMdpBaselinesTest, RandomMatchesTheEnvAndTheLearnersRankBetweenItAndTheOracle) {
  const auto tasks = EnvTasks(200, 10, 5, 3);
  // The same MDPs run through the env with uniformly random actions: the
  // baselines' simulation must give the same expected trial return.
  TabularMdpEnv env(TabularMdpEnv::Config{10, 5, 10, false});
  env.SeedTask(3);
  env.Seed(9);
  Rng action_rng(4);
  double env_total = 0.0;
  for (size_t i = 0; i < tasks.size(); ++i) {
    env.ResetTaskState();
    for (int episode = 0; episode < 100; ++episode) {
      env.Reset();
      for (int t = 0; t < 10; ++t) {
        const float action[1] = {static_cast<float>(action_rng.UniformInt(5))};
        env_total += env.Step(action).reward;
      }
    }
  }
  const double env_trial_return = env_total / (static_cast<double>(tasks.size()) * 10.0);

  const BaselineResult random = RunTabularMdpBaseline("random", tasks, 10, 10, 100, 1);
  // 20,000 trials each side: standard errors about 0.04
  EXPECT_NEAR(random.mean_trial_return, env_trial_return, 0.25);
  EXPECT_NEAR(random.mean_trial_return, 50.0, 2.5);  // E[R] = 0.5 per step

  const double oracle = RunTabularMdpBaseline("oracle", tasks, 10, 10, 20, 1).mean_trial_return;
  for (const char* name : {"greedy", "epsilon-greedy", "psrl"}) {
    const BaselineResult r = RunTabularMdpBaseline(name, tasks, 10, 10, 20, 1);
    EXPECT_GT(r.mean_trial_return, random.mean_trial_return + 5.0) << name;
    EXPECT_LT(r.mean_trial_return, oracle - 2.0) << name;
  }
  EXPECT_GT(oracle, random.mean_trial_return + 15.0);
}

TEST(TabularMdpBaselinesTest, AKnownMdpIsSolvedAndRunsAreDeterministic) {
  // Two states, two actions; action 1 in state 0 always pays and stays.
  const TabularMdp sure{2, 2, {0.0, 1.0, 0.0, 0.0}, {0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0, 1.0}};
  EXPECT_DOUBLE_EQ(RunTabularMdpBaseline("oracle", {sure}, 3, 5, 4, 1).mean_trial_return, 15.0);
  // greedy tries action 0 once (it moves to state 1, where nothing pays for
  // the rest of the episode), then sticks to action 1 from the second episode
  EXPECT_DOUBLE_EQ(RunTabularMdpBaseline("greedy", {sure}, 3, 5, 4, 1).mean_trial_return, 10.0);
  const auto tasks = EnvTasks(5, 4, 3, 8);
  EXPECT_EQ(RunTabularMdpBaseline("psrl", tasks, 5, 10, 3, 7).mean_trial_return,
            RunTabularMdpBaseline("psrl", tasks, 5, 10, 3, 7).mean_trial_return);
}

TEST(TabularMdpBaselinesTest, BadInputIsRefusedWithTheReason) {
  const TabularMdp ok{1, 2, {0.5, 0.5}, {1.0, 1.0}};
  EXPECT_THROW(RunTabularMdpBaseline("ucrl2", {ok}, 10, 10, 1, 1), ConfigError);
  EXPECT_THROW(RunTabularMdpBaseline("random", {}, 10, 10, 1, 1), ConfigError);
  EXPECT_THROW(RunTabularMdpBaseline("random", {ok}, 0, 10, 1, 1), ConfigError);
  EXPECT_THROW(
      RunTabularMdpBaseline("random", {TabularMdp{1, 2, {0.5, 1.5}, {1.0, 1.0}}}, 10, 10, 1, 1),
      ConfigError);
  EXPECT_THROW(
      RunTabularMdpBaseline("random", {TabularMdp{1, 2, {0.5, 0.5}, {1.0, 0.5}}}, 10, 10, 1, 1),
      ConfigError);
  EXPECT_THROW(RunTabularMdpBaseline("random", {ok, TabularMdp{1, 1, {0.5}, {1.0}}}, 10, 10, 1, 1),
               ConfigError);
}

}  // namespace
}  // namespace manyworlds::classic
