#include "manyworlds/classic/two_goal_maze.h"

#include <gtest/gtest.h>

#include <vector>

#include "manyworlds/core/error.h"
#include "tests/classic/test_util.h"

namespace manyworlds::classic::testing {
namespace {

using Maze = TwoGoalMazeEnv;

TaskState MazeTask(int64_t goal) { return TaskState{"two-goal-maze", {{"goal", goal}}}; }

// Walks a path; returns the last step and checks every earlier step costs
// 0.01 without ending the episode.
StepResult Walk(Env& env, const std::vector<int>& path) {
  StepResult r;
  for (size_t i = 0; i < path.size(); ++i) {
    const float action[1] = {static_cast<float>(path[i])};
    r = env.Step(action);
    if (i + 1 < path.size()) {
      EXPECT_FLOAT_EQ(r.reward, -0.01f) << "step " << i;
      EXPECT_FALSE(r.terminated) << "step " << i;
    }
  }
  return r;
}

const std::vector<int> kToLeftGoal = {Maze::kUp,   Maze::kUp,   Maze::kUp,  Maze::kUp,
                                      Maze::kLeft, Maze::kLeft, Maze::kLeft};
const std::vector<int> kToRightGoal = {Maze::kUp,    Maze::kUp,    Maze::kUp,   Maze::kUp,
                                       Maze::kRight, Maze::kRight, Maze::kRight};

TEST(ClassicTwoGoalMazeTest, StartsAtTheBottomOfTheStem) {
  Maze env(Maze::Config{});
  env.SetTaskState(MazeTask(1));
  EXPECT_EQ(env.Reset().env_obs, (std::vector<float>{0.5f, 0.0f}));
  EXPECT_EQ(env.task_obs()[0], 1.0f);
}

TEST(ClassicTwoGoalMazeTest, PayingGoalGivesPlusOneAndSuccess) {
  for (int goal : {0, 1}) {
    Maze env(Maze::Config{});
    env.SetTaskState(MazeTask(goal));
    env.Reset();
    StepResult r = Walk(env, goal == 0 ? kToLeftGoal : kToRightGoal);
    EXPECT_EQ(r.reward, 1.0f);
    EXPECT_TRUE(r.terminated);
    EXPECT_FALSE(r.truncated);
    EXPECT_EQ(r.info.Get("success"), 1.0f);
    EXPECT_EQ(r.obs.env_obs, (std::vector<float>{goal == 0 ? 0.0f : 1.0f, 1.0f}));
  }
}

TEST(ClassicTwoGoalMazeTest, OtherGoalGivesMinusOneAndNoSuccess) {
  for (int goal : {0, 1}) {
    Maze env(Maze::Config{});
    env.SetTaskState(MazeTask(goal));
    env.Reset();
    StepResult r = Walk(env, goal == 0 ? kToRightGoal : kToLeftGoal);
    EXPECT_EQ(r.reward, -1.0f);
    EXPECT_TRUE(r.terminated);
    EXPECT_EQ(r.info.Get("success"), 0.0f);
  }
}

TEST(ClassicTwoGoalMazeTest, WallsBlockMovement) {
  Maze env(Maze::Config{});
  env.SetTaskState(MazeTask(0));
  env.Reset();
  for (int action : {Maze::kDown, Maze::kLeft, Maze::kRight}) {
    const float a[1] = {static_cast<float>(action)};
    StepResult r = env.Step(a);
    EXPECT_EQ(r.obs.env_obs, (std::vector<float>{0.5f, 0.0f})) << "action " << action;
    EXPECT_FLOAT_EQ(r.reward, -0.01f);
  }
  // Half-way up the stem the side walls still block; the top of the bar too.
  StepResult r = Walk(env, {Maze::kUp, Maze::kUp, Maze::kLeft, Maze::kRight});
  EXPECT_EQ(r.obs.env_obs, (std::vector<float>{0.5f, 0.5f}));
  r = Walk(env, {Maze::kUp, Maze::kUp, Maze::kUp});
  EXPECT_EQ(r.obs.env_obs, (std::vector<float>{0.5f, 1.0f}));
  EXPECT_EQ(env.y(), 4);
}

TEST(ClassicTwoGoalMazeTest, TruncatesWithoutReachingAGoal) {
  Maze env(Maze::Config{50, false});
  env.SetTaskState(MazeTask(0));
  env.Reset();
  const float down[1] = {static_cast<float>(Maze::kDown)};
  StepResult r;
  for (int i = 0; i < 50; ++i) r = env.Step(down);
  EXPECT_TRUE(r.truncated);
  EXPECT_FALSE(r.terminated);
  EXPECT_EQ(r.info.Get("success"), 0.0f);
}

TEST(ClassicTwoGoalMazeTest, BothGoalsAreSampled) {
  Maze env(Maze::Config{});
  int ones = 0;
  for (uint64_t seed = 0; seed < 40; ++seed) {
    env.SeedTask(seed);
    ones += static_cast<int>(env.SampleTaskState().params["goal"].get<int64_t>());
  }
  EXPECT_GT(ones, 5);
  EXPECT_LT(ones, 35);
}

TEST(ClassicTwoGoalMazeTest, RejectsGoalsOtherThanZeroOrOne) {
  Maze env(Maze::Config{});
  EXPECT_THROW(env.SetTaskState(MazeTask(2)), TaskStateError);
  EXPECT_THROW(env.SetTaskState(MazeTask(-1)), TaskStateError);
  EXPECT_THROW(env.SetTaskState(TaskState{"two-goal-maze", {{"goal", 0.5}}}), TaskStateError);
}

}  // namespace
}  // namespace manyworlds::classic::testing
