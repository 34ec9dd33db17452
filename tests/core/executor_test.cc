#include "manyworlds/core/executor.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "tests/core/toy_env.h"

namespace manyworlds {
namespace {

using ::manyworlds::testing::ToyEnv;

constexpr int kNumEnvs = 7;

// Short, varied episode limits so that auto-resets happen often and at
// different times in different envs.
int64_t MaxStepsFor(int i) { return 5 + 3 * i; }
bool DiscreteFor(int i) { return i % 3 == 1; }

std::unique_ptr<Env> MakeToy(int i) {
  return std::make_unique<ToyEnv>(DiscreteFor(i), MaxStepsFor(i));
}

std::vector<std::unique_ptr<Env>> MakeToys(int n = kNumEnvs) {
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < n; ++i) envs.push_back(MakeToy(i));
  return envs;
}

// A valid action batch for step t: Discrete rows get {0, 1, 2}, Box rows
// values in [-1.5, 1.5] (clipped by the env).
std::vector<float> Actions(int t, int n = kNumEnvs) {
  Rng rng(MixSeed(1234, static_cast<uint64_t>(t)));
  std::vector<float> actions(n);
  for (int i = 0; i < n; ++i) {
    actions[i] = DiscreteFor(i) ? static_cast<float>(rng.UniformInt(3))
                                : static_cast<float>(rng.Uniform(-1.5, 1.5));
  }
  return actions;
}

// Everything the executor exposes after a step.
struct Snapshot {
  std::vector<float> env_obs, task_obs, rewards, info, final_env_obs, final_task_obs;
  std::vector<bool> terminated, truncated;
  std::vector<int64_t> episode_steps;

  explicit Snapshot(const BatchedExecutor& e)
      : env_obs(e.env_obs().begin(), e.env_obs().end()),
        task_obs(e.task_obs().begin(), e.task_obs().end()),
        rewards(e.rewards().begin(), e.rewards().end()),
        info(e.info().begin(), e.info().end()),
        final_env_obs(e.final_env_obs().begin(), e.final_env_obs().end()),
        final_task_obs(e.final_task_obs().begin(), e.final_task_obs().end()),
        terminated(e.terminated().begin(), e.terminated().end()),
        truncated(e.truncated().begin(), e.truncated().end()),
        episode_steps(e.episode_steps().begin(), e.episode_steps().end()) {}
};

// Bitwise float comparison (NaN-safe, -0 != +0).
bool SameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void ExpectSame(const Snapshot& a, const Snapshot& b, int step) {
  EXPECT_TRUE(SameBits(a.env_obs, b.env_obs)) << "step " << step;
  EXPECT_TRUE(SameBits(a.task_obs, b.task_obs)) << "step " << step;
  EXPECT_TRUE(SameBits(a.rewards, b.rewards)) << "step " << step;
  EXPECT_TRUE(SameBits(a.info, b.info)) << "step " << step;
  EXPECT_TRUE(SameBits(a.final_env_obs, b.final_env_obs)) << "step " << step;
  EXPECT_TRUE(SameBits(a.final_task_obs, b.final_task_obs)) << "step " << step;
  EXPECT_EQ(a.terminated, b.terminated) << "step " << step;
  EXPECT_EQ(a.truncated, b.truncated) << "step " << step;
  EXPECT_EQ(a.episode_steps, b.episode_steps) << "step " << step;
}

std::vector<Snapshot> RunBatch(int num_threads, int steps, bool async) {
  BatchedExecutor exec(MakeToys(), {.num_threads = num_threads});
  exec.Seed(5, 6);
  exec.Reset();
  std::vector<Snapshot> out;
  out.emplace_back(exec);
  for (int t = 0; t < steps; ++t) {
    const std::vector<float> actions = Actions(t);
    if (async) {
      exec.Send(actions);
      exec.Recv();
    } else {
      exec.Step(actions);
    }
    out.emplace_back(exec);
  }
  return out;
}

TEST(ExecutorTest, BufferShapes) {
  BatchedExecutor exec(MakeToys(), {.num_threads = 2});
  EXPECT_EQ(exec.num_envs(), kNumEnvs);
  EXPECT_EQ(exec.num_threads(), 2);
  EXPECT_EQ(exec.action_size(), 1);
  EXPECT_EQ(exec.env_obs_size(), 2);
  EXPECT_EQ(exec.task_obs_size(), 1);
  EXPECT_EQ(exec.info_fields(), (std::vector<std::string>{"success", "distance"}));
  EXPECT_EQ(exec.env_obs().size(), kNumEnvs * 2u);
  EXPECT_EQ(exec.task_obs().size(), kNumEnvs * 1u);
  EXPECT_EQ(exec.rewards().size(), kNumEnvs * 1u);
  EXPECT_EQ(exec.terminated().size(), kNumEnvs * 1u);
  EXPECT_EQ(exec.truncated().size(), kNumEnvs * 1u);
  EXPECT_EQ(exec.info().size(), kNumEnvs * 2u);
  EXPECT_EQ(exec.final_env_obs().size(), kNumEnvs * 2u);
  EXPECT_EQ(exec.final_task_obs().size(), kNumEnvs * 1u);
  EXPECT_EQ(exec.episode_steps().size(), kNumEnvs * 1u);
  EXPECT_EQ(exec.env(3).id(), "toy");
  EXPECT_EQ(exec.env(1).id(), "toy-discrete");
  EXPECT_THROW(exec.env(kNumEnvs), Error);
  EXPECT_THROW(exec.env(-1), Error);
}

TEST(ExecutorTest, MoreThreadsThanEnvsAreClamped) {
  BatchedExecutor exec(MakeToys(2), {.num_threads = 8});
  EXPECT_EQ(exec.num_threads(), 2);
  exec.Reset();
  exec.Step(Actions(0, 2));
}

TEST(ExecutorTest, ResultsDoNotDependOnThreadCount) {
  constexpr int kSteps = 400;
  const std::vector<Snapshot> one = RunBatch(1, kSteps, false);
  // Enough steps that every env has auto-reset several times.
  int resets = 0;
  for (const Snapshot& s : one) {
    for (int i = 0; i < kNumEnvs; ++i) resets += s.terminated[i] || s.truncated[i];
  }
  EXPECT_GT(resets, 3 * kNumEnvs);
  for (int threads : {2, 3}) {
    const std::vector<Snapshot> many = RunBatch(threads, kSteps, false);
    ASSERT_EQ(one.size(), many.size());
    for (size_t t = 0; t < one.size(); ++t) ExpectSame(one[t], many[t], static_cast<int>(t));
  }
}

TEST(ExecutorTest, SendRecvEqualsStep) {
  constexpr int kSteps = 150;
  const std::vector<Snapshot> sync = RunBatch(1, kSteps, false);
  for (int threads : {1, 2, 3}) {
    const std::vector<Snapshot> async = RunBatch(threads, kSteps, true);
    ASSERT_EQ(sync.size(), async.size());
    for (size_t t = 0; t < sync.size(); ++t) ExpectSame(sync[t], async[t], static_cast<int>(t));
  }
}

TEST(ExecutorTest, SyncAndAsyncCallsCanBeMixed) {
  constexpr int kSteps = 60;
  const std::vector<Snapshot> sync = RunBatch(1, kSteps, false);
  BatchedExecutor exec(MakeToys(), {.num_threads = 2});
  exec.Seed(5, 6);
  exec.Reset();
  for (int t = 0; t < kSteps; ++t) {
    const std::vector<float> actions = Actions(t);
    if (t % 3 == 0) {
      exec.Send(actions);
      exec.Recv();
    } else {
      exec.Step(actions);
    }
    ExpectSame(sync[t + 1], Snapshot(exec), t + 1);
  }
}

TEST(ExecutorTest, MatchesSteppingEachEnvByHand) {
  constexpr uint64_t kEnvSeed = 77, kTaskSeed = 88;
  constexpr int kSteps = 200;
  for (int threads : {1, 2}) {
    BatchedExecutor exec(MakeToys(), {.num_threads = threads});
    exec.Seed(kEnvSeed, kTaskSeed);
    exec.Reset();

    std::vector<std::unique_ptr<Env>> ref = MakeToys();
    for (int i = 0; i < kNumEnvs; ++i) {
      ref[i]->Seed(MixSeed(kEnvSeed, i));
      ref[i]->SeedTask(MixSeed(kTaskSeed, i));
      const Observation obs = ref[i]->Reset();
      EXPECT_EQ(exec.env_obs()[2 * i], obs.env_obs[0]);
      EXPECT_EQ(exec.env_obs()[2 * i + 1], obs.env_obs[1]);
      EXPECT_EQ(exec.task_obs()[i], obs.task_obs[0]);
    }
    int ended = 0;
    for (int t = 0; t < kSteps; ++t) {
      const std::vector<float> actions = Actions(t);
      exec.Step(actions);
      for (int i = 0; i < kNumEnvs; ++i) {
        const StepResult r = ref[i]->Step(std::span<const float>(&actions[i], 1));
        EXPECT_EQ(exec.rewards()[i], r.reward);
        EXPECT_EQ(exec.terminated()[i], r.terminated);
        EXPECT_EQ(exec.truncated()[i], r.truncated);
        EXPECT_EQ(exec.info()[2 * i], r.info.values[0]);
        EXPECT_EQ(exec.info()[2 * i + 1], r.info.values[1]);
        if (r.terminated || r.truncated) {
          ++ended;
          // The last observation of the episode is kept aside...
          EXPECT_EQ(exec.final_env_obs()[2 * i], r.obs.env_obs[0]);
          EXPECT_EQ(exec.final_env_obs()[2 * i + 1], r.obs.env_obs[1]);
          EXPECT_EQ(exec.final_task_obs()[i], r.obs.task_obs[0]);
          // ...and the obs rows hold the first observation of the next one.
          const Observation first = ref[i]->Reset();
          EXPECT_EQ(exec.env_obs()[2 * i], first.env_obs[0]);
          EXPECT_EQ(exec.env_obs()[2 * i + 1], first.env_obs[1]);
          EXPECT_EQ(exec.task_obs()[i], first.task_obs[0]);
          EXPECT_EQ(exec.episode_steps()[i], 0);
        } else {
          EXPECT_EQ(exec.env_obs()[2 * i], r.obs.env_obs[0]);
          EXPECT_EQ(exec.env_obs()[2 * i + 1], r.obs.env_obs[1]);
          EXPECT_EQ(exec.task_obs()[i], r.obs.task_obs[0]);
          EXPECT_EQ(exec.episode_steps()[i], ref[i]->elapsed_steps());
        }
      }
    }
    EXPECT_GT(ended, kNumEnvs);
  }
}

TEST(ExecutorTest, SeedUsesMixSeedPerEnv) {
  BatchedExecutor exec(MakeToys(), {.num_threads = 1});
  exec.Seed(3, 4);
  for (int i = 0; i < kNumEnvs; ++i) {
    ToyEnv ref(DiscreteFor(i), MaxStepsFor(i));
    ref.Seed(MixSeed(3, i));
    ref.SeedTask(MixSeed(4, i));
    EXPECT_EQ(exec.env(i).SampleTaskState(), ref.SampleTaskState());
    const Observation a = exec.env(i).Reset();
    const Observation b = ref.Reset();
    EXPECT_EQ(a.env_obs, b.env_obs);
    EXPECT_EQ(a.task_obs, b.task_obs);
  }
  // Different envs get different streams.
  EXPECT_NE(exec.env(0).SampleTaskState(), exec.env(2).SampleTaskState());
}

TEST(ExecutorTest, SetTaskStateResetsOnlyThatEnv) {
  BatchedExecutor exec(MakeToys(), {.num_threads = 2});
  exec.Seed(1, 2);
  exec.Reset();
  for (int t = 0; t < 3; ++t) exec.Step(Actions(t));
  const Snapshot before(exec);
  std::vector<int64_t> elapsed;
  for (int i = 0; i < kNumEnvs; ++i) elapsed.push_back(exec.env(i).elapsed_steps());

  const TaskState task{"toy", {{"target", 0.5}}};
  exec.SetTaskState(3, task);
  EXPECT_EQ(exec.env(3).GetTaskState(), task);
  EXPECT_FLOAT_EQ(exec.task_obs()[3], 0.5f);
  EXPECT_EQ(exec.episode_steps()[3], 0);
  EXPECT_EQ(exec.env(3).elapsed_steps(), 0);
  EXPECT_FALSE(exec.env(3).needs_reset());
  // The new episode's first position is in [-0.1, 0.1].
  EXPECT_LE(std::abs(exec.env_obs()[6]), 0.1f);
  EXPECT_EQ(exec.env_obs()[7], 0.0f);
  for (int i = 0; i < kNumEnvs; ++i) {
    if (i == 3) continue;
    EXPECT_EQ(exec.env(i).elapsed_steps(), elapsed[i]);
    EXPECT_EQ(exec.episode_steps()[i], before.episode_steps[i]);
    EXPECT_EQ(exec.env_obs()[2 * i], before.env_obs[2 * i]);
    EXPECT_EQ(exec.env_obs()[2 * i + 1], before.env_obs[2 * i + 1]);
    EXPECT_EQ(exec.task_obs()[i], before.task_obs[i]);
  }
  exec.Step(Actions(3));  // every env, env 3 included, can step on
  EXPECT_EQ(exec.episode_steps()[3], 1);
  // A foreign task state is rejected.
  EXPECT_THROW(exec.SetTaskState(3, TaskState{"cartpole", {{"target", 0.5}}}), TaskStateError);
  EXPECT_THROW(exec.SetTaskState(kNumEnvs, task), Error);
}

// ToyEnv with another env_obs size or another info field.
class WideToy : public ToyEnv {
 public:
  WideToy() {
    const float inf = std::numeric_limits<float>::infinity();
    mutable_spec().env_obs_space = Space::Box(-inf, inf, {3});
  }
};
class OtherInfoToy : public ToyEnv {
 public:
  OtherInfoToy() { mutable_spec().info_fields = {"success", "dist"}; }
};

TEST(ExecutorTest, RejectsBadConfigurations) {
  EXPECT_THROW(BatchedExecutor({}), ConfigError);
  {
    std::vector<std::unique_ptr<Env>> envs = MakeToys(2);
    envs.push_back(nullptr);
    EXPECT_THROW(BatchedExecutor(std::move(envs)), ConfigError);
  }
  EXPECT_THROW(BatchedExecutor(MakeToys(2), {.num_threads = 0}), ConfigError);
  {
    std::vector<std::unique_ptr<Env>> envs = MakeToys(2);
    envs.push_back(std::make_unique<WideToy>());
    try {
      BatchedExecutor exec(std::move(envs));
      FAIL() << "mismatched env_obs size accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("env_obs size"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("env 2"), std::string::npos) << e.what();
    }
  }
  {
    std::vector<std::unique_ptr<Env>> envs = MakeToys(2);
    envs.push_back(std::make_unique<OtherInfoToy>());
    EXPECT_THROW(BatchedExecutor(std::move(envs)), ConfigError);
  }
}

TEST(ExecutorTest, RejectsWrongActionBufferLength) {
  for (int threads : {1, 2}) {
    BatchedExecutor exec(MakeToys(), {.num_threads = threads});
    exec.Reset();
    std::vector<float> short_actions(kNumEnvs - 1, 0.0f);
    std::vector<float> long_actions(kNumEnvs + 1, 0.0f);
    EXPECT_THROW(exec.Step(short_actions), InvalidActionError);
    EXPECT_THROW(exec.Step(long_actions), InvalidActionError);
    EXPECT_THROW(exec.Send(long_actions), InvalidActionError);
    // Nothing was stepped.
    for (int i = 0; i < kNumEnvs; ++i) EXPECT_EQ(exec.env(i).elapsed_steps(), 0);
    exec.Step(Actions(0));
  }
}

TEST(ExecutorTest, EnvErrorIsRethrownLowestIndexFirstAndResetRecovers) {
  for (int threads : {1, 2, 3}) {
    for (bool async : {false, true}) {
      BatchedExecutor exec(MakeToys(), {.num_threads = threads});
      exec.Reset();
      std::vector<float> actions = Actions(0);
      actions[5] = std::numeric_limits<float>::quiet_NaN();  // Box env 5
      actions[4] = 7.0f;                                     // Discrete env 4: out of range
      try {
        if (async) {
          exec.Send(actions);
          exec.Recv();
        } else {
          exec.Step(actions);
        }
        FAIL() << "invalid actions accepted";
      } catch (const InvalidActionError& e) {
        EXPECT_NE(std::string(e.what()).find("toy-discrete"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("Discrete(3)"), std::string::npos) << e.what();
      }
      // The error is reported once; the executor is usable after Reset.
      exec.Reset();
      exec.Step(Actions(1));
      exec.Send(Actions(2));
      exec.Recv();
      for (int i = 0; i < kNumEnvs; ++i) EXPECT_EQ(exec.episode_steps()[i], 2);
    }
  }
}

// ToyEnv that throws a non-manyworlds exception from its dynamics.
class ExplodingToy : public ToyEnv {
 public:
  bool armed = false;

 protected:
  void DoStep(std::span<const float> action, const StepView& out) override {
    if (armed) throw std::runtime_error("boom");
    ToyEnv::DoStep(action, out);
  }
};

TEST(ExecutorTest, ForeignExceptionsPropagate) {
  for (int threads : {1, 2}) {
    std::vector<std::unique_ptr<Env>> envs;
    for (int i = 0; i < 4; ++i) envs.push_back(std::make_unique<ExplodingToy>());
    BatchedExecutor exec(std::move(envs), {.num_threads = threads});
    exec.Reset();
    static_cast<ExplodingToy&>(exec.env(2)).armed = true;
    const std::vector<float> actions(4, 0.5f);
    EXPECT_THROW(exec.Step(actions), std::runtime_error);
    static_cast<ExplodingToy&>(exec.env(2)).armed = false;
    exec.Reset();
    exec.Step(actions);
  }
}

TEST(ExecutorTest, WithoutAutoResetSteppingAnEndedEnvFails) {
  for (int threads : {1, 2}) {
    std::vector<std::unique_ptr<Env>> envs;
    for (int i = 0; i < 3; ++i) envs.push_back(std::make_unique<ToyEnv>(false, 3));
    BatchedExecutor exec(std::move(envs), {.num_threads = threads, .auto_reset = false});
    exec.Seed(9, 9);
    exec.Reset();
    // Targets far from the start so that only the time limit ends episodes.
    for (int i = 0; i < 3; ++i) exec.SetTaskState(i, TaskState{"toy", {{"target", 1.0}}});
    const std::vector<float> actions(3, -1.0f);
    for (int t = 0; t < 3; ++t) exec.Step(actions);
    for (int i = 0; i < 3; ++i) {
      EXPECT_TRUE(exec.truncated()[i]);
      EXPECT_FALSE(exec.terminated()[i]);
      EXPECT_EQ(exec.episode_steps()[i], 3);
      EXPECT_TRUE(exec.env(i).needs_reset());
    }
    EXPECT_THROW(exec.Step(actions), EpisodeStateError);
    exec.Reset();
    exec.Step(actions);
    EXPECT_EQ(exec.episode_steps()[0], 1);
  }
}

TEST(ExecutorTest, StepBeforeResetFails) {
  BatchedExecutor exec(MakeToys(), {.num_threads = 2});
  EXPECT_THROW(exec.Step(Actions(0)), EpisodeStateError);
  exec.Reset();
  exec.Step(Actions(0));
}

TEST(ExecutorTest, AsyncProtocolIsChecked) {
  for (int threads : {1, 2}) {
    BatchedExecutor exec(MakeToys(), {.num_threads = threads});
    exec.Reset();
    EXPECT_THROW(exec.Recv(), EpisodeStateError);
    exec.Send(Actions(0));
    EXPECT_THROW(exec.Send(Actions(1)), EpisodeStateError);
    EXPECT_THROW(exec.Step(Actions(1)), EpisodeStateError);
    EXPECT_THROW(exec.Reset(), EpisodeStateError);
    exec.Recv();
    exec.Send(Actions(1));
    // Destroying the executor with a Send in flight is safe.
  }
}

}  // namespace
}  // namespace manyworlds
