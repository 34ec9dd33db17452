#include "manyworlds/classic/point_nav.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "manyworlds/classic/point_nav_sparse.h"
#include "manyworlds/core/error.h"
#include "tests/classic/test_util.h"

namespace manyworlds::classic::testing {
namespace {

TaskState GoalTask(double x, double y) {
  return TaskState{"point-nav", {{"goal", std::vector<double>{x, y}}}};
}
TaskState AngleTask(double angle) { return TaskState{"point-nav-sparse", {{"angle", angle}}}; }

// A step of length 0.1 toward the goal (or the remaining distance).
std::vector<float> Toward(const std::array<double, 2>& position,
                          const std::array<double, 2>& goal) {
  const double dx = goal[0] - position[0], dy = goal[1] - position[1];
  const double scale = std::min(1.0, 0.1 / std::max(std::hypot(dx, dy), 1e-12));
  return {static_cast<float>(dx * scale), static_cast<float>(dy * scale)};
}

TEST(ClassicPointNavTest, RewardIsMinusDistanceAndGrowsTowardTheGoal) {
  PointNavEnv env(PointNavEnv::Config{});
  env.SetTaskState(GoalTask(0.3, -0.4));
  EXPECT_EQ(env.Reset().env_obs, (std::vector<float>{0.0f, 0.0f}));
  EXPECT_EQ(std::vector<float>(env.task_obs().begin(), env.task_obs().end()),
            (std::vector<float>{0.3f, -0.4f}));
  float last_reward = -0.5f;  // distance from the start
  for (int i = 0; i < 4; ++i) {
    StepResult r = env.Step(Toward(env.position(), env.goal()));
    EXPECT_GT(r.reward, last_reward) << "step " << i;
    const double distance = std::hypot(env.position()[0] - 0.3, env.position()[1] + 0.4);
    EXPECT_FLOAT_EQ(r.reward, static_cast<float>(-distance));
    EXPECT_FLOAT_EQ(r.info.Get("distance"), static_cast<float>(distance));
    EXPECT_EQ(r.info.Get("success"), 0.0f);
    last_reward = r.reward;
  }
  // 0.4 walked of 0.5: one more step arrives.
  StepResult r = env.Step(Toward(env.position(), env.goal()));
  EXPECT_NEAR(r.reward, 0.0f, 1e-6);
  EXPECT_EQ(r.info.Get("success"), 1.0f);
  EXPECT_FALSE(r.terminated);
  // Walking away lowers the reward.
  const float away[2] = {-0.1f, 0.0f};
  EXPECT_LT(env.Step(away).reward, r.reward);
}

TEST(ClassicPointNavTest, ActionsAreClippedToTenthPerAxis) {
  PointNavEnv env(PointNavEnv::Config{});
  env.SetTaskState(GoalTask(0.0, 0.0));
  env.Reset();
  const float big[2] = {3.0f, -0.05f};
  StepResult r = env.Step(big);
  EXPECT_EQ(r.obs.env_obs, (std::vector<float>{0.1f, -0.05f}));
}

TEST(ClassicPointNavTest, NeverTerminatesAndTruncatesAtHorizon) {
  PointNavEnv env(PointNavEnv::Config{0.5, 100, false});
  env.SetTaskState(GoalTask(0.0, 0.0));
  env.Reset();
  const float stay[2] = {0.0f, 0.0f};
  for (int i = 1; i <= 100; ++i) {
    StepResult r = env.Step(stay);  // sitting on the goal
    EXPECT_FALSE(r.terminated);
    EXPECT_EQ(r.info.Get("success"), 1.0f);
    EXPECT_EQ(r.truncated, i == 100);
  }
}

TEST(ClassicPointNavTest, GoalRangeBoundsSampledAndAcceptedGoals) {
  PointNavEnv narrow(PointNavEnv::Config{0.5, 100, false});
  EXPECT_THROW(narrow.SetTaskState(GoalTask(0.7, 0.0)), TaskStateError);
  PointNavEnv wide(PointNavEnv::Config{2.0, 100, false});
  EXPECT_NO_THROW(wide.SetTaskState(GoalTask(0.7, -1.9)));
  double largest = 0.0;
  for (uint64_t seed = 0; seed < 50; ++seed) {
    wide.SeedTask(seed);
    wide.ResetTaskState();
    for (double g : wide.goal()) {
      EXPECT_LE(std::abs(g), 2.0);
      largest = std::max(largest, std::abs(g));
    }
  }
  EXPECT_GT(largest, 1.0);
}

TEST(ClassicPointNavSparseTest, GoalsLieOnTheUpperUnitHalfCircle) {
  PointNavSparseEnv env(PointNavSparseEnv::Config{});
  for (uint64_t seed = 0; seed < 50; ++seed) {
    env.SeedTask(seed);
    env.ResetTaskState();
    EXPECT_NEAR(std::hypot(env.goal()[0], env.goal()[1]), 1.0, 1e-12);
    EXPECT_GE(env.goal()[1], 0.0);
    EXPECT_EQ(env.task_obs()[0], static_cast<float>(env.goal()[0]));
    EXPECT_EQ(env.task_obs()[1], static_cast<float>(env.goal()[1]));
  }
}

TEST(ClassicPointNavSparseTest, RewardOnlyInsideTheGoalRadius) {
  PointNavSparseEnv env(PointNavSparseEnv::Config{});
  env.SetTaskState(AngleTask(PointNavSparseEnv::kPi / 2));  // goal (0, 1)
  env.Reset();
  const float up[2] = {0.0f, 0.1f};
  for (int i = 1; i <= 7; ++i) {
    StepResult r = env.Step(up);  // distance 1 - 0.1 i >= 0.3
    EXPECT_EQ(r.reward, 0.0f) << "step " << i;
    EXPECT_EQ(r.info.Get("success"), 0.0f);
    EXPECT_NEAR(r.info.Get("distance"), 1.0 - 0.1 * i, 1e-6);
  }
  env.Step(up);  // distance 0.2: on the boundary, not tested
  StepResult r = env.Step(up);
  EXPECT_EQ(r.reward, 1.0f);
  EXPECT_EQ(r.info.Get("success"), 1.0f);
  EXPECT_FALSE(r.terminated);
  const float right[2] = {0.1f, 0.0f};
  for (int i = 0; i < 3; ++i) r = env.Step(right);  // (0.3, 0.9): distance 0.316
  EXPECT_EQ(r.reward, 0.0f);
}

TEST(ClassicPointNavSparseTest, GoalRadiusOptionWidensThePayingDisc) {
  PointNavSparseEnv env(PointNavSparseEnv::Config{1.5, 30, false});
  env.SetTaskState(AngleTask(0.0));
  env.Reset();
  const float stay[2] = {0.0f, 0.0f};
  EXPECT_EQ(env.Step(stay).reward, 1.0f);  // start is at distance 1 < 1.5
}

TEST(ClassicPointNavSparseTest, RejectsAnglesOutsideTheHalfCircle) {
  PointNavSparseEnv env(PointNavSparseEnv::Config{});
  EXPECT_THROW(env.SetTaskState(AngleTask(-0.1)), TaskStateError);
  EXPECT_THROW(env.SetTaskState(AngleTask(3.2)), TaskStateError);
  EXPECT_NO_THROW(env.SetTaskState(AngleTask(PointNavSparseEnv::kPi)));
}

}  // namespace
}  // namespace manyworlds::classic::testing
