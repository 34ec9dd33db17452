#include "manyworlds/classic/acrobot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/classic/test_util.h"

namespace manyworlds::classic::testing {
namespace {

TaskState AcrobotTask(const std::vector<double>& mu) { return TaskState{"acrobot", {{"mu", mu}}}; }

constexpr double kPi = AcrobotEnv::kPi;

TEST(ClassicAcrobotTest, TaskSetsLinksAndTorqueSign) {
  const auto p = AcrobotEnv::PhysicsFromMu({0, 0, 0, 0, 0});
  EXPECT_EQ(p.l1, 1.0);
  EXPECT_EQ(p.l2, 1.0);
  EXPECT_EQ(p.m1, 1.0);
  EXPECT_EQ(p.m2, 1.0);
  EXPECT_EQ(p.lc1, 0.5);
  EXPECT_EQ(p.lc2, 0.5);
  EXPECT_EQ(p.torque_sign, 1.0);
  const auto q = AcrobotEnv::PhysicsFromMu({1, -1, 0.5, -0.5, -0.01});
  EXPECT_EQ(q.l1, 1.5);
  EXPECT_EQ(q.l2, 0.5);
  EXPECT_EQ(q.lc1, 0.75);
  EXPECT_EQ(q.lc2, 0.25);
  EXPECT_EQ(q.m1, 1.25);
  EXPECT_EQ(q.m2, 0.75);
  EXPECT_EQ(q.torque_sign, -1.0);
}

TEST(ClassicAcrobotTest, HangingAtRestIsAnEquilibrium) {
  const auto p = AcrobotEnv::PhysicsFromMu({0.2, -0.4, 0.6, 0.1, 0.5});
  const auto d = AcrobotEnv::Derivative(p, {0, 0, 0, 0}, 0.0);
  for (double v : d) EXPECT_NEAR(v, 0.0, 1e-12);
}

TEST(ClassicAcrobotTest, OneRk4StepMatchesReferenceValues) {
  // Reference: Gym's book equations and one classic RK4 step of 0.2 s with
  // unit links, evaluated independently in double precision, from
  // (t1, t2, t1_dot, t2_dot) = (0.3, -0.2, 0.5, -1.0) with torque +1.
  const auto next =
      AcrobotEnv::Integrate(AcrobotEnv::PhysicsFromMu({}), {0.3, -0.2, 0.5, -1.0}, 1.0);
  EXPECT_NEAR(next[0], 0.3422438766639251, 1e-12);
  EXPECT_NEAR(next[1], -0.30931685281977855, 1e-12);
  EXPECT_NEAR(next[2], -0.08717174222764312, 1e-12);
  EXPECT_NEAR(next[3], -0.07306921813854794, 1e-12);
}

TEST(ClassicAcrobotTest, WrapsAnglesAndClipsVelocities) {
  const auto p = AcrobotEnv::PhysicsFromMu({});
  const auto next = AcrobotEnv::Integrate(p, {3.1, -3.1, 40.0, -40.0}, 0.0);
  EXPECT_GE(next[0], -kPi);
  EXPECT_LT(next[0], kPi);
  EXPECT_GE(next[1], -kPi);
  EXPECT_LT(next[1], kPi);
  EXPECT_LE(std::abs(next[2]), AcrobotEnv::kMaxVel1);
  EXPECT_LE(std::abs(next[3]), AcrobotEnv::kMaxVel2);
}

TEST(ClassicAcrobotTest, TerminalConditionUsesTheTasksLinks) {
  const auto unit = AcrobotEnv::PhysicsFromMu({});
  EXPECT_FALSE(AcrobotEnv::IsTerminal(unit, {0, 0, 0, 0}));        // hanging
  EXPECT_TRUE(AcrobotEnv::IsTerminal(unit, {kPi, 0, 0, 0}));       // upright
  EXPECT_FALSE(AcrobotEnv::IsTerminal(unit, {kPi / 2, 0, 0, 0}));  // horizontal: height 0
  // Gym's test with unit links: -cos t1 - cos(t1 + t2) > 1.
  EXPECT_TRUE(AcrobotEnv::IsTerminal(unit, {2.2, 0.3, 0, 0}));   // 0.589 + 0.801 > 1
  EXPECT_FALSE(AcrobotEnv::IsTerminal(unit, {1.8, 0.3, 0, 0}));  // 0.227 + 0.505 < 1
  // Long first link, short second (l1 = 1.5, l2 = 0.5): threshold 1.
  const auto uneven = AcrobotEnv::PhysicsFromMu({1, -1, 0, 0, 0});
  EXPECT_FALSE(AcrobotEnv::IsTerminal(uneven, {kPi / 2, kPi / 2, 0, 0}));  // height 0.5
  EXPECT_TRUE(AcrobotEnv::IsTerminal(uneven, {2.5, 0.0, 0, 0}));           // 2 * 0.801 > 1
}

TEST(ClassicAcrobotTest, NegativeMu4FlipsTheTorque) {
  AcrobotEnv plain(AcrobotEnv::Config{});
  AcrobotEnv flipped(AcrobotEnv::Config{});
  plain.SetTaskState(AcrobotTask({0.1, 0.2, -0.3, 0.4, 0.5}));
  flipped.SetTaskState(AcrobotTask({0.1, 0.2, -0.3, 0.4, -0.5}));
  plain.Seed(7);
  flipped.Seed(7);
  EXPECT_EQ(plain.Reset().env_obs, flipped.Reset().env_obs);
  for (int i = 0; i < 30; ++i) {
    const float a[1] = {static_cast<float>(i % 3)};
    const float mirrored[1] = {static_cast<float>(2 - i % 3)};
    ASSERT_EQ(plain.Step(a).obs.env_obs, flipped.Step(mirrored).obs.env_obs) << "step " << i;
  }
}

TEST(ClassicAcrobotTest, EnergyPumpingReachesTheGoal) {
  AcrobotEnv env(AcrobotEnv::Config{});
  env.SetTaskState(AcrobotTask({0, 0, 0, 0, 0}));
  Observation obs = env.Reset();
  StepResult r;
  int steps = 0;
  do {
    // Bang-bang torque against the first joint's velocity pumps energy into
    // the swing (swings up in ~80 steps from the Gym start states).
    const float a[1] = {obs.env_obs[4] > 0.0f ? 0.0f : 2.0f};
    r = env.Step(a);
    obs = r.obs;
    ++steps;
    if (!r.terminated) {
      EXPECT_EQ(r.reward, -1.0f);
      EXPECT_EQ(r.info.Get("success"), 0.0f);
    }
  } while (!r.terminated && !r.truncated);
  EXPECT_TRUE(r.terminated) << "no swing-up in " << steps << " steps";
  EXPECT_EQ(r.reward, 0.0f);
  EXPECT_EQ(r.info.Get("success"), 1.0f);
  EXPECT_TRUE(AcrobotEnv::IsTerminal(env.physics(), env.state()));
}

}  // namespace
}  // namespace manyworlds::classic::testing
