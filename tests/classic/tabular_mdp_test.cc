#include "manyworlds/classic/tabular_mdp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "manyworlds/core/error.h"
#include "tests/classic/test_util.h"

namespace manyworlds::classic::testing {
namespace {

TEST(ClassicTabularMdpTest, SampledTaskIsAValidMdpAndTheTaskObservation) {
  TabularMdpEnv env(TabularMdpEnv::Config{});
  env.SeedTask(3);
  env.ResetTaskState();
  const int64_t s_count = 4, a_count = 5;
  ASSERT_EQ(env.task_obs().size(), static_cast<size_t>(s_count * a_count * (1 + s_count)));
  for (int64_t s = 0; s < s_count; ++s) {
    for (int64_t a = 0; a < a_count; ++a) {
      EXPECT_GE(env.reward_mean(s, a), 0.0);
      EXPECT_LT(env.reward_mean(s, a), 1.0);
      EXPECT_EQ(env.task_obs()[s * a_count + a], static_cast<float>(env.reward_mean(s, a)));
      double total = 0.0;
      for (int64_t n = 0; n < s_count; ++n) {
        EXPECT_GT(env.transition(s, a, n), 0.0);
        total += env.transition(s, a, n);
        EXPECT_EQ(env.task_obs()[s_count * a_count + (s * a_count + a) * s_count + n],
                  static_cast<float>(env.transition(s, a, n)));
      }
      EXPECT_NEAR(total, 1.0, 1e-12);
    }
  }
}

TEST(ClassicTabularMdpTest, EmpiricalTransitionsAndRewardsMatchTheTask) {
  const int64_t s_count = 3, a_count = 2;
  TabularMdpEnv env(TabularMdpEnv::Config{s_count, a_count, 10, false});
  env.SetMaxEpisodeSteps(0);
  env.SeedTask(12);
  env.ResetTaskState();
  env.Seed(5);
  env.Reset();
  std::vector<double> counts(s_count * a_count * s_count, 0.0);
  std::vector<double> visits(s_count * a_count, 0.0);
  std::vector<double> rewards(s_count * a_count, 0.0);
  Rng action_rng(1);
  int64_t state = 0;
  for (int i = 0; i < 120000; ++i) {
    const auto a = static_cast<int64_t>(action_rng.UniformInt(a_count));
    const float action[1] = {static_cast<float>(a)};
    StepResult r = env.Step(action);
    ASSERT_EQ(r.info.Get("expected_reward"), static_cast<float>(env.reward_mean(state, a)));
    const int64_t next = env.state();
    ASSERT_EQ(r.obs.env_obs[next], 1.0f);
    ASSERT_EQ(r.obs.env_obs[s_count], r.reward);
    counts[(state * a_count + a) * s_count + next] += 1.0;
    visits[state * a_count + a] += 1.0;
    rewards[state * a_count + a] += r.reward;
    state = next;
  }
  for (int64_t s = 0; s < s_count; ++s) {
    for (int64_t a = 0; a < a_count; ++a) {
      const double n = visits[s * a_count + a];
      ASSERT_GT(n, 2000.0) << "(s, a) = (" << s << ", " << a << ") rarely visited";
      // 4.5 standard deviations of a frequency estimated from n samples.
      const double tolerance = 4.5 * 0.5 / std::sqrt(n);
      EXPECT_NEAR(rewards[s * a_count + a] / n, env.reward_mean(s, a), tolerance);
      for (int64_t next = 0; next < s_count; ++next) {
        EXPECT_NEAR(counts[(s * a_count + a) * s_count + next] / n, env.transition(s, a, next),
                    tolerance);
      }
    }
  }
}

// P[s, a] moves deterministically to (s + a + 1) mod S; R[s, a] is 0 or 1.
TaskState DeterministicTask(int64_t s_count, int64_t a_count) {
  std::vector<double> rewards(s_count * a_count), transitions(s_count * a_count * s_count, 0.0);
  for (int64_t s = 0; s < s_count; ++s) {
    for (int64_t a = 0; a < a_count; ++a) {
      rewards[s * a_count + a] = (s + a) % 2 == 0 ? 1.0 : 0.0;
      transitions[(s * a_count + a) * s_count + (s + a + 1) % s_count] = 1.0;
    }
  }
  return TaskState{"tabular-mdp",
                   {{"n_states", s_count},
                    {"n_actions", a_count},
                    {"rewards", rewards},
                    {"transitions", transitions}}};
}

TEST(ClassicTabularMdpTest, FollowsADeterministicTaskExactly) {
  TabularMdpEnv env(TabularMdpEnv::Config{});
  env.SetTaskState(DeterministicTask(4, 5));
  Observation obs = env.Reset();
  EXPECT_EQ(obs.env_obs, (std::vector<float>{1, 0, 0, 0, 0}));
  int64_t s = 0;
  for (int64_t a : {0, 2, 1, 4, 3, 0, 0}) {
    const float action[1] = {static_cast<float>(a)};
    StepResult r = env.Step(action);
    EXPECT_EQ(r.reward, (s + a) % 2 == 0 ? 1.0f : 0.0f);
    s = (s + a + 1) % 4;
    std::vector<float> expected(5, 0.0f);
    expected[s] = 1.0f;
    expected[4] = r.reward;
    EXPECT_EQ(r.obs.env_obs, expected);
    EXPECT_FALSE(r.terminated);
  }
  EXPECT_EQ(env.Reset().env_obs, (std::vector<float>{1, 0, 0, 0, 0}));
}

TEST(ClassicTabularMdpTest, RejectsInvalidTransitionsAndForeignSizes) {
  TabularMdpEnv env(TabularMdpEnv::Config{});
  TaskState bad_row = DeterministicTask(4, 5);
  bad_row.params["transitions"][0] = 0.5;  // row (0, 0) now sums to 1.5
  EXPECT_THROW(env.SetTaskState(bad_row), TaskStateError);
  EXPECT_THROW(env.SetTaskState(DeterministicTask(3, 5)), TaskStateError);
  TaskState wrong_count = DeterministicTask(4, 5);
  wrong_count.params["n_actions"] = 4;
  EXPECT_THROW(env.SetTaskState(wrong_count), TaskStateError);
  EXPECT_NO_THROW(env.SetTaskState(DeterministicTask(4, 5)));
}

}  // namespace
}  // namespace manyworlds::classic::testing
