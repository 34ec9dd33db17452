#include "manyworlds/core/wrappers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "tests/core/toy_env.h"

namespace manyworlds {
namespace {

using testing::ToyEnv;

std::unique_ptr<Env> Toy(bool discrete = false, int64_t max_steps = 50) {
  return std::make_unique<ToyEnv>(discrete, max_steps);
}

// Same action, env-observation space and info fields as ToyEnv, but a task
// observation of 3 values: for MultiEnv members that differ in task obs.
class WideTaskEnv : public Env {
 public:
  WideTaskEnv() : Env(MakeSpec()) {}

 protected:
  static EnvSpec MakeSpec() {
    EnvSpec spec = ToyEnv::MakeSpec(false, 30);
    spec.id = "wide-task";
    spec.task_obs_space = Space::Box(0.0f, 1.0f, {3});
    return spec;
  }
  TaskState DoSampleTaskState(Rng& rng) override {
    return TaskState{id(), {{"level", rng.Uniform()}}};
  }
  TaskState DoGetTaskState() const override { return TaskState{id(), {{"level", level_}}}; }
  void DoSetTaskState(const TaskState& state) override {
    TaskStateReader reader(state, id());
    reader.ExpectKeys({"level"});
    level_ = reader.Number("level", 0.0, 1.0);
    const float obs[3] = {static_cast<float>(level_), 0.0f, 1.0f};
    SetTaskObs(obs);
  }
  void DoReset(const ObsView& out) override {
    out.env_obs[0] = static_cast<float>(env_rng().Uniform());
    out.env_obs[1] = static_cast<float>(level_);
  }
  void DoStep(std::span<const float> action, const StepView& out) override {
    out.env_obs[0] = action[0];
    out.env_obs[1] = static_cast<float>(level_);
  }

 private:
  double level_ = 0.0;
};

// A ToyEnv whose spec differs in one field, for MultiEnv mismatch errors.
class EditedToy : public ToyEnv {
 public:
  explicit EditedToy(int what) {
    if (what == 0) mutable_spec().info_fields = {"success", "dist"};
    if (what == 1) mutable_spec().env_obs_space = Space::Box(-2.0f, 2.0f, {3});
  }
};

template <typename Fn>
std::string ErrorOf(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "<no error>";
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TaskState ToyTask(double target) { return TaskState{"toy", {{"target", target}}}; }

TEST(WrapperIdTest, EachWrapperAddsASuffix) {
  EXPECT_EQ(NTasks(Toy(), 3).id(), "toy|ntasks(3)");
  EXPECT_EQ(NTasksId(Toy(), 3).id(), "toy|ntasks-id(3)");
  EXPECT_EQ(NTasksId(Toy(), 3, TaskIdEncoding::kOneHot).id(), "toy|ntasks-id(3,one-hot)");
  EXPECT_EQ(SampleRandomTask(Toy()).id(), "toy|sample-random-task");
  EXPECT_EQ(TimeLimit(Toy(), 7).id(), "toy|time-limit(7)");
  EXPECT_EQ(AppendTaskOneHot(std::make_unique<NTasksId>(Toy(), 2)).id(),
            "toy|ntasks-id(2)|task-one-hot");
  std::vector<std::unique_ptr<Env>> envs;
  envs.push_back(Toy());
  envs.push_back(std::make_unique<WideTaskEnv>());
  EXPECT_EQ(MultiEnv(std::move(envs)).id(), "multi-env(toy,wide-task)");
}

TEST(NTasksWrapperTest, SamplesOnlyFromAFixedSetOfNTasks) {
  NTasks env(Toy(), 3);
  env.SeedTask(5);
  std::set<std::string> seen;
  for (int i = 0; i < 200; ++i) seen.insert(env.SampleTaskState().Dump());
  ASSERT_EQ(seen.size(), 3u);
  ASSERT_EQ(env.tasks().size(), 3u);
  for (const auto& task : env.tasks()) EXPECT_TRUE(seen.count(task.Dump())) << task.Dump();
}

TEST(NTasksWrapperTest, TheSetAndTheDrawsDependOnlyOnTheTaskSeed) {
  auto draws = [](uint64_t task_seed) {
    NTasks env(Toy(), 4);
    env.SeedTask(task_seed);
    std::vector<std::string> out;
    for (int i = 0; i < 20; ++i) out.push_back(env.SampleTaskState().Dump());
    return out;
  };
  EXPECT_EQ(draws(7), draws(7));
  EXPECT_NE(draws(7), draws(8));
  // The set stays fixed for the env's lifetime, even across SeedTask.
  NTasks env(Toy(), 2);
  const std::vector<TaskState> before = env.tasks();
  env.SeedTask(123);
  EXPECT_EQ(env.tasks(), before);
}

TEST(NTasksWrapperTest, TaskStatesAreTheInnerEnvsAndRunAnywhere) {
  NTasks env(Toy(), 3);
  const TaskState state = env.SampleTaskState();
  EXPECT_EQ(state.env, "toy");
  ToyEnv plain;
  plain.SetTaskState(TaskState::Parse(state.Dump()));
  EXPECT_EQ(plain.GetTaskState(), state);
  env.SetTaskState(state);
  EXPECT_EQ(env.task_obs()[0], plain.task_obs()[0]);
}

TEST(NTasksWrapperTest, RejectsFewerThanOneTask) {
  EXPECT_THROW(NTasks(Toy(), 0), ConfigError);
  EXPECT_TRUE(Contains(ErrorOf([] { NTasks(Toy(), -2); }), "'toy'"));
  EXPECT_THROW(NTasksId(Toy(), 0), ConfigError);
}

TEST(NTasksIdWrapperTest, IndexEncodingShowsTheTaskIndex) {
  NTasksId env(Toy(), 4);
  EXPECT_EQ(env.spec().task_obs_space, Space::Discrete(4));
  env.SeedTask(3);
  std::set<int> indices;
  for (int i = 0; i < 30; ++i) {
    env.ResetTaskState();
    const Observation obs = env.Reset();
    const TaskState state = env.GetTaskState();
    ASSERT_EQ(obs.task_obs.size(), 1u);
    EXPECT_EQ(obs.task_obs[0], static_cast<float>(env.task_index()));
    EXPECT_EQ(state.params["index"].get<int>(), env.task_index());
    // The inner env runs the cached task of that index.
    EXPECT_EQ(TaskState::FromJson(state.params["task"]), env.tasks()[env.task_index()]);
    indices.insert(env.task_index());
  }
  EXPECT_EQ(indices.size(), 4u);
}

TEST(NTasksIdWrapperTest, OneHotEncodingShowsAOneHotVector) {
  NTasksId env(Toy(true), 3, TaskIdEncoding::kOneHot);
  EXPECT_EQ(env.spec().task_obs_space, Space::Box(0.0f, 1.0f, {3}));
  for (int i = 0; i < 10; ++i) {
    env.ResetTaskState();
    const Observation obs = env.Reset();
    std::vector<float> expected(3, 0.0f);
    expected[env.task_index()] = 1.0f;
    EXPECT_EQ(obs.task_obs, expected);
    const StepResult r = env.Step(std::vector<float>{1.0f});
    EXPECT_EQ(r.obs.task_obs, expected);
  }
}

TEST(NTasksIdWrapperTest, TaskStateIsSelfContainedAcrossInstances) {
  NTasksId a(Toy(), 5);
  a.Seed(1);
  a.SeedTask(1);
  a.ResetTaskState();
  const std::string text = a.GetTaskState().Dump();
  const Observation obs_a = a.Reset();

  // Another instance with another task seed drew another set; the state
  // still carries everything needed.
  NTasksId b(Toy(), 5);
  b.Seed(1);
  b.SeedTask(999);
  b.ResetTaskState();
  b.SetTaskState(TaskState::Parse(text));
  EXPECT_EQ(b.GetTaskState().Dump(), text);
  EXPECT_EQ(b.task_index(), a.task_index());
  const Observation obs_b = b.Reset();
  EXPECT_EQ(obs_a.env_obs, obs_b.env_obs);
  EXPECT_EQ(obs_a.task_obs, obs_b.task_obs);
  const std::vector<float> action{0.3f};
  EXPECT_EQ(a.Step(action).obs.env_obs, b.Step(action).obs.env_obs);
}

TEST(NTasksIdWrapperTest, RejectsBadTaskStatesWithReadableErrors) {
  NTasksId env(Toy(), 3);
  const std::string id = env.id();
  const nlohmann::json inner = ToyTask(0.5).ToJson();
  auto set = [&](const nlohmann::json& params) { env.SetTaskState(TaskState{id, params}); };
  EXPECT_NO_THROW(set({{"index", 2}, {"task", inner}}));
  EXPECT_TRUE(Contains(ErrorOf([&] { set({{"index", 3}, {"task", inner}}); }), "'index'"));
  EXPECT_THROW(set({{"index", -1}, {"task", inner}}), TaskStateError);
  EXPECT_THROW(set({{"index", 0.5}, {"task", inner}}), TaskStateError);
  EXPECT_TRUE(Contains(ErrorOf([&] { set({{"index", 0}}); }), "'task' is missing"));
  EXPECT_THROW(set({{"index", 0}, {"task", 3}}), TaskStateError);
  EXPECT_THROW(set({{"index", 0}, {"task", inner}, {"extra", 1}}), TaskStateError);
  const std::string foreign_inner = ErrorOf([&] {
    set({{"index", 0}, {"task", TaskState{"cartpole", nlohmann::json::object()}.ToJson()}});
  });
  EXPECT_TRUE(Contains(foreign_inner, "rejected by env 'toy'")) << foreign_inner;
  EXPECT_THROW(set({{"index", 0}, {"task", ToyTask(5.0).ToJson()}}), TaskStateError);
  EXPECT_THROW(env.SetTaskState(TaskState{"toy", {{"index", 0}, {"task", inner}}}), TaskStateError);
  // A rejected state leaves the previous task in place.
  EXPECT_EQ(env.task_index(), 2);
  EXPECT_EQ(env.GetTaskState().params["task"], inner);
}

TEST(SampleRandomTaskWrapperTest, EveryResetSamplesANewTask) {
  SampleRandomTask env(Toy());
  env.SeedTask(4);
  std::set<std::string> tasks;
  for (int i = 0; i < 10; ++i) {
    const Observation obs = env.Reset();
    const TaskState state = env.GetTaskState();
    tasks.insert(state.Dump());
    EXPECT_EQ(obs.task_obs[0], static_cast<float>(state.params["target"].get<double>()));
  }
  EXPECT_EQ(tasks.size(), 10u);
}

TEST(SampleRandomTaskWrapperTest, AnExplicitTaskIsUsedForTheNextEpisodeOnly) {
  SampleRandomTask env(Toy());
  env.SetTaskState(ToyTask(0.25));
  env.Reset();
  EXPECT_EQ(env.GetTaskState(), ToyTask(0.25));
  env.Reset();
  EXPECT_NE(env.GetTaskState(), ToyTask(0.25));
}

TEST(SampleRandomTaskWrapperTest, OuterWrappersSeeTheResampledTaskObservation) {
  TimeLimit env(std::make_unique<SampleRandomTask>(Toy()), 10);
  for (int i = 0; i < 5; ++i) {
    const Observation obs = env.Reset();
    const double target = env.GetTaskState().params["target"].get<double>();
    EXPECT_EQ(obs.task_obs[0], static_cast<float>(target));
    EXPECT_EQ(env.task_obs()[0], static_cast<float>(target));
  }
}

std::unique_ptr<MultiEnv> ToyAndWide() {
  std::vector<std::unique_ptr<Env>> envs;
  envs.push_back(Toy(false, 20));
  envs.push_back(std::make_unique<WideTaskEnv>());
  return std::make_unique<MultiEnv>(std::move(envs));
}

TEST(MultiEnvWrapperTest, TaskIsTheEnvIndexAndStepsGoToTheSelectedEnv) {
  auto env = ToyAndWide();
  EXPECT_EQ(env->spec().task_obs_space, Space::Discrete(2));
  EXPECT_EQ(env->spec().env_obs_space, env->env(0).spec().env_obs_space);
  EXPECT_EQ(env->spec().max_episode_steps, 30);
  env->SetTaskState(TaskState{
      env->id(), {{"index", 1}, {"task", {{"env", "wide-task"}, {"params", {{"level", 0.5}}}}}}});
  const Observation obs = env->Reset();
  EXPECT_EQ(obs.task_obs, std::vector<float>{1.0f});
  EXPECT_EQ(obs.env_obs[1], 0.5f);
  const StepResult r = env->Step(std::vector<float>{0.75f});
  EXPECT_EQ(r.obs.env_obs[0], 0.75f);
  EXPECT_EQ(env->env(1).elapsed_steps(), 1);
  EXPECT_TRUE(env->env(0).needs_reset());
  EXPECT_EQ(env->active_index(), 1);
}

TEST(MultiEnvWrapperTest, SamplesEveryEnvAndRoundTripsTaskStatesAcrossInstances) {
  auto a = ToyAndWide();
  a->SeedTask(9);
  std::set<int> indices;
  for (int i = 0; i < 40; ++i) {
    const TaskState state = a->SampleTaskState();
    EXPECT_EQ(state.env, a->id());
    indices.insert(state.params["index"].get<int>());
    auto b = ToyAndWide();
    b->SetTaskState(TaskState::Parse(state.Dump()));
    EXPECT_EQ(b->GetTaskState(), state);
  }
  EXPECT_EQ(indices.size(), 2u);
}

TEST(MultiEnvWrapperTest, SeedsMembersWithDifferentSeeds) {
  std::vector<std::unique_ptr<Env>> envs;
  envs.push_back(Toy());
  envs.push_back(Toy());
  MultiEnv env(std::move(envs));
  env.Seed(3);
  std::vector<float> starts;
  for (int index : {0, 1}) {
    env.SetTaskState(TaskState{env.id(), {{"index", index}, {"task", ToyTask(0.9).ToJson()}}});
    starts.push_back(env.Reset().env_obs[0]);
  }
  EXPECT_NE(starts[0], starts[1]);
}

TEST(MultiEnvWrapperTest, MismatchedMembersAreConfigErrorsNamingTheMismatch) {
  auto make = [](std::unique_ptr<Env> second) {
    std::vector<std::unique_ptr<Env>> envs;
    envs.push_back(Toy());
    envs.push_back(std::move(second));
    MultiEnv env(std::move(envs));
  };
  const std::string action = ErrorOf([&] { make(Toy(true)); });
  EXPECT_TRUE(Contains(action, "env 1 ('toy-discrete') has action space Discrete(3)")) << action;
  const std::string info = ErrorOf([&] { make(std::make_unique<EditedToy>(0)); });
  EXPECT_TRUE(Contains(info, "info fields [success, dist]")) << info;
  const std::string obs = ErrorOf([&] { make(std::make_unique<EditedToy>(1)); });
  EXPECT_TRUE(Contains(obs, "env observation space")) << obs;
  EXPECT_THROW(make(Toy(true)), ConfigError);
  EXPECT_THROW(MultiEnv(std::vector<std::unique_ptr<Env>>{}), ConfigError);
  EXPECT_THROW(make(nullptr), ConfigError);
}

// A ToyEnv whose observations are bounded, for the union of member spaces.
class BoundedToy : public ToyEnv {
 public:
  BoundedToy(float low, float high) {
    mutable_spec().env_obs_space = Space::Box({low, 0.0f}, {high, 1.0f}, {2});
  }
};

TEST(MultiEnvWrapperTest, ObservationSpaceIsTheUnionOfTheMembers) {
  std::vector<std::unique_ptr<Env>> envs;
  envs.push_back(std::make_unique<BoundedToy>(-1.0f, 2.0f));
  envs.push_back(std::make_unique<BoundedToy>(-3.0f, 1.0f));
  MultiEnv env(std::move(envs));
  EXPECT_EQ(env.spec().env_obs_space.low(), (std::vector<float>{-3.0f, 0.0f}));
  EXPECT_EQ(env.spec().env_obs_space.high(), (std::vector<float>{2.0f, 1.0f}));
}

TEST(MultiEnvWrapperTest, RejectsBadTaskStates) {
  auto env = ToyAndWide();
  auto set = [&](const nlohmann::json& params) { env->SetTaskState(TaskState{env->id(), params}); };
  EXPECT_THROW(set({{"index", 2}, {"task", ToyTask(0.1).ToJson()}}), TaskStateError);
  // Env 1 cannot run a task of env 0.
  EXPECT_THROW(set({{"index", 1}, {"task", ToyTask(0.1).ToJson()}}), TaskStateError);
  EXPECT_THROW(set(nlohmann::json::array()), TaskStateError);
}

TEST(TimeLimitWrapperTest, TruncatesAtTheLimit) {
  TimeLimit env(Toy(false, 50), 5);
  EXPECT_EQ(env.spec().max_episode_steps, 5);
  env.SetTaskState(ToyTask(0.9));
  env.Reset();
  const std::vector<float> stay{0.0f};
  for (int step = 1; step <= 5; ++step) {
    const StepResult r = env.Step(stay);
    EXPECT_FALSE(r.terminated);
    EXPECT_EQ(r.truncated, step == 5) << step;
  }
  EXPECT_THROW(env.Step(stay), EpisodeStateError);
  EXPECT_THROW(TimeLimit(Toy(), 0), ConfigError);
}

TEST(TimeLimitWrapperTest, AShorterInnerLimitStillApplies) {
  TimeLimit env(Toy(false, 4), 100);
  EXPECT_EQ(env.spec().max_episode_steps, 4);
  env.SetTaskState(ToyTask(0.9));
  env.Reset();
  const std::vector<float> stay{0.0f};
  StepResult r;
  for (int step = 0; step < 4; ++step) r = env.Step(stay);
  EXPECT_TRUE(r.truncated);
  EXPECT_EQ(env.elapsed_steps(), 4);
}

TEST(AppendTaskOneHotWrapperTest, AppendsTheOneHotIdWithUnitBounds) {
  auto make = [] {
    auto env = std::make_unique<AppendTaskOneHot>(std::make_unique<NTasksId>(Toy(), 3));
    env->Seed(2);
    env->SeedTask(2);
    return env;
  };
  auto env = make();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(env->spec().env_obs_space,
            Space::Box({-inf, -inf, 0.0f, 0.0f, 0.0f}, {inf, inf, 1.0f, 1.0f, 1.0f}, {5}));
  EXPECT_EQ(env->spec().task_obs_space, Space::Discrete(3));
  // A twin without the wrapper gives the prefix.
  NTasksId plain(Toy(), 3);
  plain.Seed(2);
  plain.SeedTask(2);
  const Observation obs = env->Reset();
  const Observation plain_obs = plain.Reset();
  const int index = static_cast<int>(plain_obs.task_obs[0]);
  std::vector<float> expected = plain_obs.env_obs;
  for (int i = 0; i < 3; ++i) expected.push_back(i == index ? 1.0f : 0.0f);
  EXPECT_EQ(obs.env_obs, expected);
  EXPECT_EQ(obs.task_obs, plain_obs.task_obs);
  const std::vector<float> action{0.5f};
  const StepResult r = env->Step(action);
  const StepResult plain_r = plain.Step(action);
  EXPECT_EQ(std::vector<float>(r.obs.env_obs.begin(), r.obs.env_obs.begin() + 2),
            plain_r.obs.env_obs);
  EXPECT_EQ(r.obs.env_obs[2 + index], 1.0f);
  EXPECT_EQ(r.reward, plain_r.reward);
}

TEST(AppendTaskOneHotWrapperTest, FollowsTasksResampledAtReset) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < 3; ++i) envs.push_back(Toy());
  AppendTaskOneHot env(
      std::make_unique<SampleRandomTask>(std::make_unique<MultiEnv>(std::move(envs))));
  std::set<int> seen;
  for (int i = 0; i < 20; ++i) {
    const Observation obs = env.Reset();
    const int index = env.GetTaskState().params["index"].get<int>();
    seen.insert(index);
    EXPECT_EQ(obs.task_obs[0], static_cast<float>(index));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(obs.env_obs[2 + k], k == index ? 1.0f : 0.0f);
  }
  EXPECT_EQ(seen.size(), 3u);
}

TEST(AppendTaskOneHotWrapperTest, NeedsADiscreteTaskObservation) {
  const std::string message = ErrorOf([] { AppendTaskOneHot env(Toy()); });
  EXPECT_TRUE(Contains(message, "Discrete(n) task observation")) << message;
  EXPECT_THROW(AppendTaskOneHot(std::make_unique<NTasksId>(Toy(), 2, TaskIdEncoding::kOneHot)),
               ConfigError);
}

}  // namespace
}  // namespace manyworlds
