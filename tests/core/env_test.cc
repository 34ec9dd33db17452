#include "manyworlds/core/env.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"
#include "tests/core/toy_env.h"

namespace manyworlds {
namespace {

using testing::ToyEnv;

TEST(EnvTest, ResetReturnsStructuredObservationAndSamplesATask) {
  ToyEnv env;
  EXPECT_FALSE(env.has_task());
  Observation obs = env.Reset();
  EXPECT_TRUE(env.has_task());
  ASSERT_EQ(obs.env_obs.size(), 2u);
  ASSERT_EQ(obs.task_obs.size(), 1u);
  EXPECT_FLOAT_EQ(obs.task_obs[0], static_cast<float>(env.target()));
  EXPECT_TRUE(env.spec().env_obs_space.Contains(obs.env_obs));
}

TEST(EnvTest, StepBeforeResetIsAnError) {
  ToyEnv env;
  const float action[1] = {0.0f};
  try {
    env.Step(action);
    FAIL() << "expected EpisodeStateError";
  } catch (const EpisodeStateError& e) {
    EXPECT_NE(std::string(e.what()).find("'toy'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("before Reset"), std::string::npos) << e.what();
  }
}

TEST(EnvTest, StepAfterTruncationIsAnErrorUntilReset) {
  ToyEnv env(/*discrete=*/false, /*max_steps=*/3);
  env.SetTaskState(TaskState{"toy", {{"target", 1.0}}});
  env.Reset();
  const float stay[1] = {0.0f};
  StepResult r;
  for (int i = 0; i < 3; ++i) {
    r = env.Step(stay);
    EXPECT_FALSE(r.terminated);
    EXPECT_EQ(r.truncated, i == 2);
  }
  EXPECT_TRUE(env.needs_reset());
  EXPECT_THROW(env.Step(stay), EpisodeStateError);
  env.Reset();
  EXPECT_NO_THROW(env.Step(stay));
}

TEST(EnvTest, TerminationEndsTheEpisode) {
  ToyEnv env(false, 1000);
  env.SetTaskState(TaskState{"toy", {{"target", 0.5}}});
  env.Reset();
  const float right[1] = {1.0f};
  StepResult r;
  int steps = 0;
  do {
    r = env.Step(right);
    ++steps;
  } while (!r.terminated && steps < 100);
  EXPECT_TRUE(r.terminated);
  EXPECT_FALSE(r.truncated);
  EXPECT_EQ(r.info.Get("success"), 1.0f);
  EXPECT_THROW(env.Step(right), EpisodeStateError);
}

TEST(EnvTest, BadActionsAreRejectedWithClearMessages) {
  ToyEnv env;
  env.Reset();
  const std::vector<float> too_long{0.0f, 0.0f};
  try {
    env.Step(too_long);
    FAIL();
  } catch (const InvalidActionError& e) {
    EXPECT_NE(std::string(e.what()).find("expected 1"), std::string::npos) << e.what();
  }
  const float nan_action[1] = {std::numeric_limits<float>::quiet_NaN()};
  EXPECT_THROW(env.Step(nan_action), InvalidActionError);
  const float inf_action[1] = {std::numeric_limits<float>::infinity()};
  EXPECT_THROW(env.Step(inf_action), InvalidActionError);
  // The episode survives a rejected action.
  const float ok[1] = {0.0f};
  EXPECT_NO_THROW(env.Step(ok));

  ToyEnv discrete(true);
  discrete.Reset();
  const float out_of_range[1] = {3.0f};
  const float fractional[1] = {1.5f};
  EXPECT_THROW(discrete.Step(out_of_range), InvalidActionError);
  EXPECT_THROW(discrete.Step(fractional), InvalidActionError);
  const float valid[1] = {2.0f};
  EXPECT_NO_THROW(discrete.Step(valid));
}

TEST(EnvTest, BoxActionsAreClipped) {
  ToyEnv a, b;
  a.Seed(3);
  b.Seed(3);
  a.SeedTask(4);
  b.SeedTask(4);
  a.Reset();
  b.Reset();
  const float big[1] = {25.0f};
  const float one[1] = {1.0f};
  StepResult ra = a.Step(big);
  StepResult rb = b.Step(one);
  EXPECT_EQ(ra.obs.env_obs, rb.obs.env_obs);
  EXPECT_EQ(ra.reward, rb.reward);
}

TEST(EnvTest, SeedsControlDynamicsAndTasksSeparately) {
  auto trajectory = [](uint64_t seed, uint64_t task_seed) {
    ToyEnv env;
    env.Seed(seed);
    env.SeedTask(task_seed);
    env.ResetTaskState();
    std::vector<float> values = env.Reset().env_obs;
    const float a[1] = {0.3f};
    for (int i = 0; i < 5; ++i) {
      auto r = env.Step(a);
      values.insert(values.end(), r.obs.env_obs.begin(), r.obs.env_obs.end());
      values.push_back(r.obs.task_obs[0]);
    }
    return values;
  };
  EXPECT_EQ(trajectory(1, 2), trajectory(1, 2));
  EXPECT_NE(trajectory(1, 2), trajectory(9, 2));
  EXPECT_NE(trajectory(1, 2), trajectory(1, 9));

  ToyEnv x, y;
  x.Seed(100);
  y.Seed(200);
  x.SeedTask(5);
  y.SeedTask(5);
  EXPECT_EQ(x.SampleTaskState(), y.SampleTaskState());
}

TEST(EnvTest, SetTaskStateEndsEpisodeAndValidates) {
  ToyEnv env;
  env.Reset();
  env.SetTaskState(TaskState{"toy", {{"target", -0.25}}});
  EXPECT_TRUE(env.needs_reset());
  EXPECT_FLOAT_EQ(env.task_obs()[0], -0.25f);
  EXPECT_EQ(env.GetTaskState().params["target"], -0.25);
  EXPECT_THROW(env.SetTaskState(TaskState{"other", {{"target", 0.0}}}), TaskStateError);
  EXPECT_THROW(env.SetTaskState(TaskState{"toy", {{"target", 5.0}}}), TaskStateError);
  EXPECT_THROW(env.SetTaskState(TaskState{"toy", {{"goal", 0.0}}}), TaskStateError);
  EXPECT_THROW(env.SetTaskState(TaskState{"toy", {{"target", 0.0}, {"x", 1}}}), TaskStateError);
  // A rejected state leaves the previous task in place.
  EXPECT_EQ(env.GetTaskState().params["target"], -0.25);
}

TEST(EnvTest, GetTaskStateBeforeAnyTaskIsAnError) {
  ToyEnv env;
  EXPECT_THROW(env.GetTaskState(), EpisodeStateError);
}

TEST(EnvTest, ViewOverloadsMatchAllocatingCalls) {
  ToyEnv a, b;
  a.Reset();
  std::vector<float> env_obs(2), task_obs(1), info(2);
  b.Reset(ObsView{env_obs, task_obs, {}});
  float reward = 0;
  bool terminated = false, truncated = false;
  const float act[1] = {0.2f};
  StepResult ra = a.Step(act);
  b.Step(act, StepView{env_obs, task_obs, &reward, &terminated, &truncated, info, {}});
  EXPECT_EQ(ra.obs.env_obs, env_obs);
  EXPECT_EQ(ra.reward, reward);
  EXPECT_EQ(ra.info.values, info);
  std::vector<float> wrong(3);
  EXPECT_THROW(b.Reset(ObsView{wrong, task_obs, {}}), Error);
}

TEST(EnvTest, MaxEpisodeStepsCanBeChanged) {
  ToyEnv env(false, 50);
  env.SetMaxEpisodeSteps(2);
  env.SetTaskState(TaskState{"toy", {{"target", 1.0}}});
  env.Reset();
  const float stay[1] = {0.0f};
  EXPECT_FALSE(env.Step(stay).truncated);
  EXPECT_TRUE(env.Step(stay).truncated);
  EXPECT_THROW(env.SetMaxEpisodeSteps(-1), ConfigError);
}

TEST(InfoTest, GetNamesMissingFields) {
  Info info{{"success"}, {1.0f}};
  EXPECT_EQ(info.Get("success"), 1.0f);
  EXPECT_FALSE(info.Find("distance").has_value());
  EXPECT_THROW(info.Get("distance"), Error);
}

}  // namespace
}  // namespace manyworlds
