#include "manyworlds/classic/cartpole.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "tests/classic/test_util.h"

namespace manyworlds::classic::testing {
namespace {

TaskState CartPoleTask(const std::vector<double>& mu) {
  return TaskState{"cartpole", {{"mu", mu}}};
}

TEST(ClassicCartPoleTest, ZeroTaskIsGymsCartPole) {
  const auto p = CartPoleEnv::PhysicsFromMu({0, 0, 0, 0, 0});
  EXPECT_EQ(p.gravity, 9.8);
  EXPECT_EQ(p.cart_mass, 1.0);
  EXPECT_EQ(p.pole_mass, 0.1);
  EXPECT_EQ(p.half_length, 0.5);
  EXPECT_EQ(p.force, 10.0);
  const auto q = CartPoleEnv::PhysicsFromMu({1, -1, 1, -1, -1});
  EXPECT_DOUBLE_EQ(q.gravity, 14.8);
  EXPECT_DOUBLE_EQ(q.cart_mass, 0.5);
  EXPECT_DOUBLE_EQ(q.pole_mass, 0.19);
  EXPECT_DOUBLE_EQ(q.half_length, 0.2);
  EXPECT_DOUBLE_EQ(q.force, 5.0);  // still positive: actions keep their meaning
}

TEST(ClassicCartPoleTest, OneEulerStepMatchesHandComputation) {
  // Worked by hand from Gym's equations with mu = 0 and action 1 (push
  // right, F = 10) from (x, x_dot, theta, theta_dot) = (0.1, -0.2, 0.05, 0.3):
  // temp = (F + m l theta_dot^2 sin theta) / M = 9.091115...,
  // theta_acc = -13.8707..., x_acc = 9.71874..., then Euler with tau 0.02.
  const auto next =
      CartPoleEnv::Integrate(CartPoleEnv::PhysicsFromMu({}), {0.1, -0.2, 0.05, 0.3}, 1);
  EXPECT_NEAR(next[0], 0.096, 1e-12);
  EXPECT_NEAR(next[1], -0.005625065781779709, 1e-12);
  EXPECT_NEAR(next[2], 0.056, 1e-12);
  EXPECT_NEAR(next[3], 0.02349585151852651, 1e-12);
}

TEST(ClassicCartPoleTest, EnvStepFollowsTheIntegrator) {
  CartPoleEnv env(CartPoleEnv::Config{});
  env.SetTaskState(CartPoleTask({0.3, -0.2, 0.5, -0.7, 0.9}));
  env.Seed(3);
  Observation obs = env.Reset();
  for (double v : env.state()) EXPECT_LE(std::abs(v), 0.05);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(obs.env_obs[i], static_cast<float>(env.state()[i]));
  for (int action : {1, 0, 0, 1}) {
    const auto expected = CartPoleEnv::Integrate(env.physics(), env.state(), action);
    const float a[1] = {static_cast<float>(action)};
    StepResult r = env.Step(a);
    EXPECT_EQ(env.state(), expected);
    EXPECT_EQ(r.reward, 1.0f);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(r.obs.env_obs[k], static_cast<float>(expected[k]));
  }
  EXPECT_DOUBLE_EQ(env.physics().force, 10.0 + 5.0 * 0.9);
}

TEST(ClassicCartPoleTest, ActionOnePushesRight) {
  const auto p = CartPoleEnv::PhysicsFromMu({});
  const CartPoleEnv::State rest{0, 0, 0, 0};
  EXPECT_GT(CartPoleEnv::Integrate(p, rest, 1)[1], 0.0);
  EXPECT_LT(CartPoleEnv::Integrate(p, rest, 0)[1], 0.0);
}

TEST(ClassicCartPoleTest, ConstantPushTerminatesWithRewardOnEveryStep) {
  CartPoleEnv env(CartPoleEnv::Config{});
  env.SetTaskState(CartPoleTask({0, 0, 0, 0, 0}));
  env.Reset();
  const float push[1] = {1.0f};
  int steps = 0;
  StepResult r;
  do {
    r = env.Step(push);
    ++steps;
    EXPECT_EQ(r.reward, 1.0f);
  } while (!r.terminated && !r.truncated);
  EXPECT_TRUE(r.terminated);
  EXPECT_LT(steps, 100);
  EXPECT_EQ(r.info.Get("success"), 0.0f);
  const auto& s = env.state();
  EXPECT_TRUE(std::abs(s[0]) > 2.4 || std::abs(s[2]) > CartPoleEnv::kThetaThreshold);
}

TEST(ClassicCartPoleTest, SurvivingToTheHorizonIsSuccess) {
  CartPoleEnv env(CartPoleEnv::Config{6, false});
  env.SetTaskState(CartPoleTask({0, 0, 0, 0, 0}));
  env.Reset();
  StepResult r;
  for (int i = 0; i < 6; ++i) {
    const float a[1] = {static_cast<float>(i % 2)};
    r = env.Step(a);
    EXPECT_EQ(r.info.Get("success"), i == 5 ? 1.0f : 0.0f);
  }
  EXPECT_TRUE(r.truncated);
  EXPECT_FALSE(r.terminated);
}

// The extreme tasks (every corner of the task box) under biased and random
// policies keep observations inside the declared space.
TEST(ClassicCartPoleTest, ExtremeTasksStayInsideTheObservationSpace) {
  CartPoleEnv env(CartPoleEnv::Config{});
  Rng rng(2);
  for (int corner = 0; corner < 32; ++corner) {
    std::vector<double> mu(5);
    for (int i = 0; i < 5; ++i) mu[i] = (corner >> i) & 1 ? 1.0 : -1.0;
    env.SetTaskState(CartPoleTask(mu));
    for (int policy = 0; policy < 3; ++policy) {
      env.Reset();
      for (int i = 0; i < 500; ++i) {
        const float a[1] = {policy < 2 ? static_cast<float>(policy)
                                       : static_cast<float>(rng.UniformInt(2))};
        StepResult r = env.Step(a);
        ASSERT_TRUE(env.spec().env_obs_space.Contains(r.obs.env_obs)) << "corner " << corner;
        if (r.terminated || r.truncated) break;
      }
    }
  }
}

}  // namespace
}  // namespace manyworlds::classic::testing
