// ActionRepeat and FrameStack, the two wrappers of MTEnv's DeepMind-Control suites (action
// repeat 2, 3 stacked frames), checked against the bare env stepped by hand.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/core/wrappers.h"
#include "tests/core/toy_env.h"

namespace manyworlds {
namespace {

using testing::ToyEnv;

std::unique_ptr<Env> Toy(int64_t limit = 50) {
  auto env = std::make_unique<ToyEnv>(false, limit);
  env->SeedTask(4);
  env->ResetTaskState();
  env->Seed(9);
  return env;
}

TEST(ActionRepeatTest, SumsTheRewardsOfRepeatStepsAndReturnsTheLastObservation) {
  ActionRepeat repeated(Toy(), 3);
  auto bare = Toy();
  repeated.SetTaskState(bare->GetTaskState());  // a wrapper's first reset draws its own task
  repeated.Seed(9);
  Observation a = repeated.Reset();
  Observation b = bare->Reset();
  EXPECT_EQ(a.env_obs, b.env_obs);
  EXPECT_EQ(repeated.spec().max_episode_steps, 17);  // ceil(50 / 3)
  const std::vector<float> action = {0.05f};
  int64_t outer = 0, inner = 0;
  for (;;) {
    const StepResult r = repeated.Step(action);
    ++outer;
    float sum = 0.0f;
    StepResult last;
    for (int k = 0; k < 3; ++k) {
      last = bare->Step(action);
      ++inner;
      sum += last.reward;
      if (last.terminated || last.truncated) break;
    }
    EXPECT_EQ(r.obs.env_obs, last.obs.env_obs) << outer;
    EXPECT_FLOAT_EQ(r.reward, sum) << outer;
    EXPECT_EQ(r.terminated, last.terminated);
    EXPECT_EQ(r.truncated, last.truncated);
    if (r.terminated || r.truncated) break;
  }
  // the inner limit of 50 ends the 17th step after 2 of its 3 repeats
  EXPECT_EQ(outer, 17);
  EXPECT_EQ(inner, 50);
  // the episode limit counts the wrapper's steps; the inner env gets n * repeat
  repeated.SetMaxEpisodeSteps(4);
  EXPECT_EQ(repeated.spec().max_episode_steps, 4);
  EXPECT_EQ(repeated.inner().spec().max_episode_steps, 12);
}

// Reports success on its second step only, and never ends an episode by itself.
class SuccessOnSecondStep : public Env {
 public:
  SuccessOnSecondStep() : Env(MakeSpec()) {}
  static EnvSpec MakeSpec() {
    EnvSpec spec;
    spec.id = "success-on-second-step";
    spec.action_space = Space::Box(-1.0f, 1.0f, {1});
    spec.env_obs_space = Space::Box(-1e6f, 1e6f, {1});
    spec.task_obs_space = Space::Box(0.0f, 1.0f, {0});
    spec.info_fields = {"success"};
    spec.max_episode_steps = 100;
    return spec;
  }

 protected:
  TaskState DoSampleTaskState(Rng&) override { return TaskState{id(), {}}; }
  TaskState DoGetTaskState() const override { return TaskState{id(), {}}; }
  void DoSetTaskState(const TaskState&) override { SetTaskObs({}); }
  void DoReset(const ObsView& out) override {
    step_ = 0;
    out.env_obs[0] = 0.0f;
  }
  void DoStep(std::span<const float>, const StepView& out) override {
    ++step_;
    out.env_obs[0] = static_cast<float>(step_);
    *out.reward = 1.0f;
    out.info[0] = step_ == 2 ? 1.0f : 0.0f;
  }

 private:
  int step_ = 0;
};

TEST(ActionRepeatTest, ASuccessInsideTheRepeatIsKept) {
  // the inner success is on step 2 of the first repeat of 3; the last inner step's info has
  // success 0, the wrapper's keeps the 1 (a success inside a repeat is not lost)
  ActionRepeat repeated(std::make_unique<SuccessOnSecondStep>(), 3);
  repeated.ResetTaskState();
  repeated.Reset();
  const StepResult first = repeated.Step(std::vector<float>{0.0f});
  EXPECT_EQ(first.obs.env_obs[0], 3.0f);
  EXPECT_EQ(first.reward, 3.0f);
  EXPECT_EQ(first.info.values[0], 1.0f);
  const StepResult second = repeated.Step(std::vector<float>{0.0f});
  EXPECT_EQ(second.info.values[0], 0.0f);
  EXPECT_EQ(repeated.spec().max_episode_steps, 34);  // ceil(100 / 3)
}

TEST(FrameStackTest, StacksTheLastFramesOldestFirstFromCopiesOfTheFirst) {
  FrameStack stacked(Toy(), 3);
  auto bare = Toy();
  stacked.SetTaskState(bare->GetTaskState());
  stacked.Seed(9);
  EXPECT_EQ(stacked.spec().env_obs_space.shape(), (std::vector<int64_t>{6}));
  const std::vector<float> o0 = stacked.Reset().env_obs;
  const std::vector<float> b0 = bare->Reset().env_obs;
  EXPECT_EQ(o0, (std::vector<float>{b0[0], b0[1], b0[0], b0[1], b0[0], b0[1]}));
  std::vector<std::vector<float>> frames = {b0, b0, b0};
  const std::vector<float> action = {0.3f};
  for (int t = 0; t < 5; ++t) {
    const std::vector<float> got = stacked.Step(action).obs.env_obs;
    frames.push_back(bare->Step(action).obs.env_obs);
    const size_t n = frames.size();
    std::vector<float> want;
    for (size_t k = n - 3; k < n; ++k) want.insert(want.end(), frames[k].begin(), frames[k].end());
    EXPECT_EQ(got, want) << t;
  }
  // a new episode starts from copies of its own first frame
  const std::vector<float> again = stacked.Reset().env_obs;
  EXPECT_EQ(std::vector<float>(again.begin(), again.begin() + 2),
            std::vector<float>(again.begin() + 4, again.end()));
}

TEST(FrameStackTest, StacksAlongTheFirstAxisOfShapedObservationsAndComposes) {
  // repeat 2 then 3 frames, MTEnv's order (its FrameStack wraps the action-repeated env)
  FrameStack env(std::make_unique<ActionRepeat>(Toy(10), 2), 3);
  EXPECT_EQ(env.spec().max_episode_steps, 5);
  EXPECT_EQ(env.spec().env_obs_space.flat_size(), 6);
  env.Seed(1);
  env.Reset();
  int steps = 0;
  for (StepResult r; !(r.terminated || r.truncated); ++steps) r = env.Step(std::vector<float>{0.0f});
  EXPECT_LE(steps, 5);
}

TEST(FrameWrappersTest, BadArgumentsAreConfigErrors) {
  EXPECT_THROW(ActionRepeat(Toy(), 0), ConfigError);
  EXPECT_THROW(ActionRepeat(Toy(), 1001), ConfigError);
  EXPECT_THROW(FrameStack(Toy(), 0), ConfigError);
  EXPECT_THROW(FrameStack(Toy(), 65), ConfigError);
  EXPECT_THROW(FrameStack(std::make_unique<ToyEnv>(false, 5), 2).Step(std::vector<float>{0.0f}),
               EpisodeStateError);
}

}  // namespace
}  // namespace manyworlds
