// Contract tests run on every classic env: registration, determinism, task
// seeding, task-state round trips and validation, spaces, hide_task.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "tests/classic/test_util.h"

namespace manyworlds::classic::testing {
namespace {

const std::vector<std::string> kIds = {"bandit",  "tabular-mdp", "two-goal-maze",   "cartpole",
                                       "acrobot", "point-nav",   "point-nav-sparse"};

TEST(ClassicRegistryTest, RegistersAllIdsWithDocumentedOptions) {
  const Registry& registry = ClassicRegistry();
  EXPECT_EQ(registry.Ids(), kIds);
  for (const auto& entry : registry.entries()) {
    SCOPED_TRACE(entry.id);
    EXPECT_EQ(entry.family, "classic");
    EXPECT_FALSE(entry.description.empty());
    std::vector<std::string> names;
    for (const auto& option : entry.options) {
      names.push_back(option.name);
      EXPECT_FALSE(option.doc.empty()) << option.name;
    }
    EXPECT_NE(std::find(names.begin(), names.end(), "hide_task"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "horizon"), names.end());
    auto env = registry.Make(entry.id);
    EXPECT_EQ(env->id(), entry.id);
    EXPECT_FALSE(env->spec().description.empty());
  }
}

TEST(ClassicRegistryTest, DefaultsMatchTheDocumentation) {
  EXPECT_EQ(Make("bandit")->spec().action_space.n(), 5);
  EXPECT_EQ(Make("bandit")->spec().max_episode_steps, 100);
  EXPECT_EQ(Make("tabular-mdp")->spec().env_obs_space.flat_size(), 5);
  EXPECT_EQ(Make("tabular-mdp")->spec().max_episode_steps, 10);
  EXPECT_EQ(Make("two-goal-maze")->spec().max_episode_steps, 50);
  EXPECT_EQ(Make("cartpole")->spec().max_episode_steps, 500);
  EXPECT_EQ(Make("acrobot")->spec().max_episode_steps, 500);
  EXPECT_EQ(Make("point-nav")->spec().max_episode_steps, 100);
  EXPECT_EQ(Make("point-nav-sparse")->spec().max_episode_steps, 30);
  EXPECT_EQ(Make("bandit", {{"horizon", 7}})->spec().max_episode_steps, 7);
  EXPECT_EQ(Make("bandit", {{"max_episode_steps", 9}})->spec().max_episode_steps, 9);
}

TEST(ClassicRegistryTest, UnknownOptionsRaiseConfigError) {
  for (const auto& id : kIds) {
    EXPECT_THROW(Make(id, {{"no_such_option", 1}}), ConfigError) << id;
  }
  EXPECT_THROW(Make("bandit", {{"n_arm", 3}}), ConfigError);
  EXPECT_THROW(Make("bandit", {{"hide_task", "maybe"}}), ConfigError);
}

// The message names the env, the option and the allowed range.
void ExpectBadOption(const std::string& id, const nlohmann::json& options,
                     const std::string& option, const std::string& allowed) {
  try {
    Make(id, options);
    ADD_FAILURE() << id << " accepted " << options.dump();
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'" + id + "'"), std::string::npos) << message;
    EXPECT_NE(message.find("'" + option + "'"), std::string::npos) << message;
    EXPECT_NE(message.find(allowed), std::string::npos) << message;
  }
}

TEST(ClassicRegistryTest, OutOfRangeOptionsRaiseConfigError) {
  ExpectBadOption("bandit", {{"n_arms", 1}}, "n_arms", "[2, 10000]");
  ExpectBadOption("bandit", {{"horizon", 0}}, "horizon", ">= 1");
  ExpectBadOption("tabular-mdp", {{"n_states", 0}}, "n_states", "[1, 100]");
  ExpectBadOption("tabular-mdp", {{"n_actions", 101}}, "n_actions", "[1, 100]");
  ExpectBadOption("two-goal-maze", {{"horizon", -3}}, "horizon", ">= 1");
  ExpectBadOption("cartpole", {{"horizon", 0}}, "horizon", ">= 1");
  ExpectBadOption("acrobot", {{"horizon", 0}}, "horizon", ">= 1");
  ExpectBadOption("point-nav", {{"goal_range", 0.0}}, "goal_range", "(0, 100]");
  ExpectBadOption("point-nav-sparse", {{"goal_radius", -0.1}}, "goal_radius", "(0, 2]");
}

TEST(ClassicRegistryTest, RegisteringTwiceFails) {
  Registry registry;
  RegisterClassicSuite(registry);
  EXPECT_THROW(RegisterClassicSuite(registry), ConfigError);
}

class ClassicEnvTest : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<Env> MakeEnv(bool hide_task = false) {
    return Make(GetParam(), {{"hide_task", hide_task}});
  }
};

TEST_P(ClassicEnvTest, SameSeedsGiveIdenticalTrajectories) {
  auto a = MakeEnv();
  auto b = MakeEnv();
  SeedBoth(*a, 11, 3);
  SeedBoth(*b, 11, 3);
  EXPECT_EQ(Rollout(*a, 600), Rollout(*b, 600));
}

TEST_P(ClassicEnvTest, DefaultSeedsAreDeterministic) {
  auto a = MakeEnv();
  auto b = MakeEnv();
  EXPECT_EQ(Rollout(*a, 200), Rollout(*b, 200));
}

TEST_P(ClassicEnvTest, TaskDependsOnlyOnTheTaskSeed) {
  auto a = MakeEnv();
  auto b = MakeEnv();
  a->Seed(1);
  b->Seed(1000);
  a->SeedTask(42);
  b->SeedTask(42);
  const TaskState first = a->SampleTaskState();
  EXPECT_EQ(first, b->SampleTaskState());
  // Running episodes draws from the env generator only.
  a->SetTaskState(first);
  Rollout(*a, 300);
  EXPECT_EQ(a->SampleTaskState(), b->SampleTaskState());
  // Other task seeds give other tasks (the maze has only two).
  int distinct = 0;
  for (uint64_t seed = 0; seed < 10; ++seed) {
    b->SeedTask(seed);
    distinct += b->SampleTaskState() != first ? 1 : 0;
  }
  EXPECT_GE(distinct, 3);
}

TEST_P(ClassicEnvTest, TaskStateRoundTripsThroughJson) {
  auto a = MakeEnv();
  a->SeedTask(8);
  const TaskState state = a->SampleTaskState();
  const std::string text = state.Dump();
  const TaskState parsed = TaskState::Parse(text);
  EXPECT_EQ(parsed, state);
  a->SetTaskState(state);
  EXPECT_EQ(a->GetTaskState(), state);

  auto b = MakeEnv();
  b->SetTaskState(parsed);
  EXPECT_EQ(b->GetTaskState().Dump(), text);
  a->Seed(4);
  b->Seed(4);
  EXPECT_EQ(Rollout(*a, 400), Rollout(*b, 400));
  std::vector<float> task_obs_a(a->task_obs().begin(), a->task_obs().end());
  std::vector<float> task_obs_b(b->task_obs().begin(), b->task_obs().end());
  EXPECT_EQ(task_obs_a, task_obs_b);
}

void ExpectRejected(Env& env, const TaskState& state, const std::string& what) {
  EXPECT_THROW(env.SetTaskState(state), TaskStateError) << what << ": " << state.Dump();
}

TEST_P(ClassicEnvTest, MalformedForeignAndOutOfRangeTaskStatesThrow) {
  auto env = MakeEnv();
  env->SeedTask(1);
  const TaskState good = env->SampleTaskState();
  ASSERT_NO_THROW(env->SetTaskState(good));

  TaskState foreign = good;
  foreign.env = "not-" + good.env;
  ExpectRejected(*env, foreign, "foreign id");
  for (const auto& other : kIds) {
    if (other == GetParam()) continue;
    auto other_env = Make(other);
    ExpectRejected(*env, other_env->SampleTaskState(), "state of " + other);
  }
  TaskState extra = good;
  extra.params["unexpected"] = 1;
  ExpectRejected(*env, extra, "extra key");
  for (const auto& [key, value] : good.params.items()) {
    TaskState missing = good;
    missing.params.erase(key);
    ExpectRejected(*env, missing, "missing " + key);
    TaskState wrong_type = good;
    wrong_type.params[key] = "x";
    ExpectRejected(*env, wrong_type, "string " + key);
    TaskState huge = good;
    huge.params[key] = 1e9;
    ExpectRejected(*env, huge, "huge " + key);
    if (value.is_array()) {
      TaskState element = good;
      element.params[key][0] = 1e9;
      ExpectRejected(*env, element, "huge element of " + key);
      element.params[key][0] = -1e9;
      ExpectRejected(*env, element, "very negative element of " + key);
      TaskState longer = good;
      longer.params[key].push_back(0.0);
      ExpectRejected(*env, longer, "longer " + key);
      TaskState nan = good;
      nan.params[key][0] = std::nan("");
      ExpectRejected(*env, nan, "NaN element of " + key);
    }
  }
  // A rejected state leaves the previous task in place.
  EXPECT_EQ(env->GetTaskState(), good);
}

TEST_P(ClassicEnvTest, ObservationsStayInTheirSpaces) {
  auto env = MakeEnv();
  const EnvSpec& spec = env->spec();
  Rng action_rng(3);
  for (uint64_t task = 0; task < 8; ++task) {
    SeedBoth(*env, task, task + 100);
    Observation obs = env->Reset();
    ASSERT_TRUE(spec.env_obs_space.Contains(obs.env_obs));
    ASSERT_TRUE(spec.task_obs_space.Contains(obs.task_obs));
    for (int i = 0; i < 300; ++i) {
      StepResult r = env->Step(spec.action_space.Sample(action_rng));
      ASSERT_TRUE(spec.env_obs_space.Contains(r.obs.env_obs)) << "step " << i;
      ASSERT_TRUE(spec.task_obs_space.Contains(r.obs.task_obs));
      ASSERT_TRUE(std::isfinite(r.reward));
      ASSERT_EQ(r.info.values.size(), spec.info_fields.size());
      for (float v : r.info.values) ASSERT_TRUE(std::isfinite(v));
      if (r.terminated || r.truncated) obs = env->Reset();
    }
  }
}

TEST_P(ClassicEnvTest, HideTaskZerosTheTaskObservationOnly) {
  auto shown = MakeEnv(false);
  auto hidden = MakeEnv(true);
  EXPECT_EQ(shown->spec().task_obs_space, hidden->spec().task_obs_space);
  SeedBoth(*shown, 2, 6);
  SeedBoth(*hidden, 2, 6);
  EXPECT_EQ(shown->GetTaskState(), hidden->GetTaskState());
  EXPECT_FALSE(AllZero(shown->task_obs()));
  EXPECT_TRUE(AllZero(hidden->task_obs()));
  Rng rng(1);
  Observation a = shown->Reset();
  Observation b = hidden->Reset();
  EXPECT_EQ(a.env_obs, b.env_obs);
  EXPECT_EQ(b.task_obs.size(), a.task_obs.size());
  EXPECT_TRUE(AllZero(b.task_obs));
  for (int i = 0; i < 100; ++i) {
    const auto action = shown->spec().action_space.Sample(rng);
    StepResult ra = shown->Step(action);
    StepResult rb = hidden->Step(action);
    ASSERT_EQ(ra.obs.env_obs, rb.obs.env_obs);
    ASSERT_EQ(ra.reward, rb.reward);
    ASSERT_TRUE(AllZero(rb.obs.task_obs));
    if (ra.terminated || ra.truncated) {
      shown->Reset();
      hidden->Reset();
    }
  }
}

TEST_P(ClassicEnvTest, TruncatesAtTheHorizonOption) {
  auto env = Make(GetParam(), {{"horizon", 3}});
  EXPECT_EQ(env->spec().max_episode_steps, 3);
  // Action 0 never ends these envs within three steps (the maze start is 7
  // steps from a goal, the cart-pole and acrobot start near rest).
  std::vector<float> action(env->spec().action_space.flat_size(), 0.0f);
  env->Reset();
  EXPECT_FALSE(env->Step(action).truncated);
  EXPECT_FALSE(env->Step(action).truncated);
  StepResult last = env->Step(action);
  EXPECT_TRUE(last.truncated);
  EXPECT_FALSE(last.terminated);
}

INSTANTIATE_TEST_SUITE_P(AllClassicEnvs, ClassicEnvTest, ::testing::ValuesIn(kIds),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace manyworlds::classic::testing
