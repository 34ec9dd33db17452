// Meta-World v3's evaluation wrappers as core wrappers, on classic envs:
// terminate-on-success ends point navigation at the goal (it never
// terminates on its own), and the recurrent meta-RL observation appends the
// action, the scaled reward and the episode-end flag.
#include <gtest/gtest.h>

#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/core/wrappers.h"
#include "tests/classic/test_util.h"

namespace manyworlds::classic::testing {
namespace {

float InfoValue(const StepResult& r, const std::string& name) {
  for (size_t i = 0; i < r.info.names.size(); ++i) {
    if (r.info.names[i] == name) return r.info.values[i];
  }
  return -1.0f;
}

TEST(MetaWrappersTest, TerminateOnSuccessEndsTheEpisodeAtTheFirstSuccess) {
  const TaskState goal{"point-nav", {{"goal", {0.1, 0.0}}}};
  auto plain = Make("point-nav");
  TerminateOnSuccess wrapped(Make("point-nav"));
  for (Env* env : {plain.get(), static_cast<Env*>(&wrapped)}) {
    env->SetTaskState(goal);
    env->Reset();
  }
  // step right until the goal: success there, termination only when wrapped
  const std::vector<float> right = {1.0f, 0.0f};
  bool reached = false;
  for (int t = 0; t < 20 && !reached; ++t) {
    const StepResult p = plain->Step(right);
    const StepResult w = wrapped.Step(right);
    EXPECT_EQ(InfoValue(p, "success"), InfoValue(w, "success"));
    EXPECT_FALSE(p.terminated);
    reached = InfoValue(w, "success") > 0.5f;
    EXPECT_EQ(w.terminated, reached) << t;
  }
  EXPECT_TRUE(reached);
  // an env without a success field is refused
  EXPECT_THROW(TerminateOnSuccess(Make("bandit")), ConfigError);
  // the registry option every env has builds the same wrapper
  auto option = Make("point-nav", {{"terminate_on_success", true}});
  option->SetTaskState(goal);
  option->Reset();
  bool ended = false;
  for (int t = 0; t < 20 && !ended; ++t) ended = option->Step(right).terminated;
  EXPECT_TRUE(ended);
  EXPECT_THROW(Make("bandit", {{"terminate_on_success", true}}), ConfigError);
}

TEST(MetaWrappersTest, RecurrentObservationAppendsActionScaledRewardAndDone) {
  RecurrentMetaObservation bandit(Make("bandit", {{"n_arms", 3}, {"horizon", 2}}), 0.1);
  EXPECT_EQ(bandit.spec().env_obs_space.flat_size(), 4 + 3 + 2);
  bandit.SetTaskState(TaskState{"bandit", {{"probs", {0.0, 1.0, 0.0}}}});
  const Observation first = bandit.Reset();
  for (int i = 4; i < 9; ++i) EXPECT_EQ(first.env_obs[i], 0.0f) << i;
  const StepResult pull = bandit.Step(std::vector<float>{1.0f});
  // inner obs (one-hot arm 1, reward 1), then one-hot action, reward / 10, not done
  const std::vector<float> expected = {0, 1, 0, 1, 0, 1, 0, 0.1f, 0};
  EXPECT_EQ(pull.obs.env_obs, expected);
  const StepResult last = bandit.Step(std::vector<float>{0.0f});
  EXPECT_TRUE(last.truncated);
  EXPECT_EQ(last.obs.env_obs[4], 1.0f);
  EXPECT_EQ(last.obs.env_obs[7], 0.0f);
  EXPECT_EQ(last.obs.env_obs[8], 1.0f);  // the episode ended

  RecurrentMetaObservation nav(Make("point-nav"), 1.0);
  EXPECT_EQ(nav.spec().env_obs_space.flat_size(), 2 + 2 + 2);
  nav.Reset();
  const StepResult step = nav.Step(std::vector<float>{0.5f, -0.25f});
  // the action as the env received it: clipped to the Box [-0.1, 0.1]
  EXPECT_FLOAT_EQ(step.obs.env_obs[2], 0.1f);
  EXPECT_FLOAT_EQ(step.obs.env_obs[3], -0.1f);
  EXPECT_EQ(step.obs.env_obs[4], step.reward);

  // the registry options build the same wrapper, outside terminate_on_success
  // (whose ends it reports as done)
  auto option = Make("point-nav", {{"recurrent_meta_obs", true},
                                   {"recurrent_meta_obs_reward_scale", 0.5},
                                   {"terminate_on_success", true}});
  EXPECT_EQ(option->spec().env_obs_space.flat_size(), 6);
  option->SetTaskState(TaskState{"point-nav", {{"goal", {0.1, 0.0}}}});
  option->Reset();
  StepResult r;
  for (int t = 0; t < 20 && !r.terminated; ++t) r = option->Step(std::vector<float>{1.0f, 0.0f});
  EXPECT_TRUE(r.terminated);
  EXPECT_FLOAT_EQ(r.obs.env_obs[4], 0.5f * r.reward);
  EXPECT_EQ(r.obs.env_obs[5], 1.0f);
  EXPECT_THROW(Make("bandit", {{"recurrent_meta_obs_reward_scale", "much"}}), ConfigError);
}

}  // namespace
}  // namespace manyworlds::classic::testing
