// The half-cheetah's task families: spaces, the env contract (CheckEnv),
// the rewards of MAML/PEARL's velocity and direction tasks recomputed from
// the simulator state, and task states.
#include "manyworlds/locomotion/half_cheetah.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "manyworlds/core/env_checker.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/core/wrapper.h"
#include "manyworlds/core/wrappers/time_limit.h"
#include "manyworlds/sim/scene_source.h"
#include "tests/support/scratch_dir.h"
#ifdef MANYWORLDS_HAS_RENDER
#include "manyworlds/sim/render.h"
#endif

namespace manyworlds::locomotion {
namespace {

HalfCheetahEnv::Config Vel() { return {CheetahTask::kVelocity, 200, true, true}; }
HalfCheetahEnv::Config Dir() { return {CheetahTask::kDirection, 100, true, true}; }

float Info(const StepResult& r, const char* name) {
  for (size_t i = 0; i < r.info.names.size(); ++i) {
    if (r.info.names[i] == name) return r.info.values[i];
  }
  return NAN;
}

TEST(HalfCheetahTest, SpacesAndTheEnvContract) {
  for (const auto& config : {Vel(), Dir()}) {
    HalfCheetahEnv env(config);
    EXPECT_EQ(env.spec().env_obs_space.flat_size(), 17);
    EXPECT_EQ(env.spec().action_space.flat_size(), 6);
    EXPECT_EQ(env.model()->nq, 9);
    EXPECT_EQ(env.model()->nu, 6);
    const CheckReport report = CheckEnv([&] { return std::make_unique<HalfCheetahEnv>(config); });
    EXPECT_TRUE(report.ok()) << report.ToString();
  }
}

TEST(HalfCheetahTest, RewardsAreTheVelocityAndDirectionTasksOnTheSimulatorState) {
  for (const auto& config : {Vel(), Dir()}) {
    HalfCheetahEnv env(config);
    env.SeedTask(4);
    env.Seed(7);
    env.Reset();
    const double goal = env.goal();
    Rng rng(11);
    for (int t = 0; t < 50; ++t) {
      std::vector<float> action(6);
      for (float& a : action) a = static_cast<float>(rng.Uniform(-1.0, 1.0));
      const double x_before = env.data()->qpos[0];
      const StepResult r = env.Step(action);
      const double velocity = (env.data()->qpos[0] - x_before) / 0.05;
      double control = 0.0;
      for (float a : action) control += 0.05 * a * a;
      ASSERT_NEAR(Info(r, "forward_velocity"), velocity, 1e-4);
      ASSERT_NEAR(Info(r, "control_cost"), control, 1e-5);
      const double expected = config.task == CheetahTask::kVelocity
                                  ? -std::abs(velocity - goal) - control
                                  : goal * velocity - control;
      ASSERT_NEAR(r.reward, expected, 1e-4) << t;
      ASSERT_EQ(Info(r, "sim_warnings"), 0.0f);
      // qpos without the root x, then qvel
      ASSERT_FLOAT_EQ(r.obs.env_obs[0], static_cast<float>(env.data()->qpos[1]));
      ASSERT_FLOAT_EQ(r.obs.env_obs[8], static_cast<float>(env.data()->qvel[0]));
    }
  }
}

TEST(HalfCheetahTest, TaskStatesAreCheckedAndHiddenByDefault) {
  HalfCheetahEnv vel(Vel());
  vel.SetTaskState(TaskState{"half-cheetah-vel", {{"goal_velocity", 1.5}}});
  EXPECT_EQ(vel.goal(), 1.5);
  EXPECT_EQ(vel.Reset().task_obs[0], 0.0f);  // hidden: meta-RL infers it
  EXPECT_THROW(vel.SetTaskState(TaskState{"half-cheetah-vel", {{"goal_velocity", 3.0}}}),
               TaskStateError);
  HalfCheetahEnv dir(Dir());
  EXPECT_THROW(dir.SetTaskState(TaskState{"half-cheetah-dir", {{"direction", 0}}}), TaskStateError);
  // sampled directions are +1 and -1, about half each
  int forward = 0;
  dir.SeedTask(1);
  for (int i = 0; i < 200; ++i) {
    const TaskState s = dir.SampleTaskState();
    const int d = s.params["direction"].get<int>();
    ASSERT_TRUE(d == 1 || d == -1);
    forward += d == 1;
  }
  EXPECT_GT(forward, 70);
  EXPECT_LT(forward, 130);
}

// The MuJoCo scene capability, found behind a wrapper: the env's own model
// and data, the camera "track", and an MJCF that MuJoCo loads on its own into
// a model with the same dynamics.
TEST(HalfCheetahTest, TheSceneIsFoundBehindWrappersAndItsXmlLoads) {
  TimeLimit wrapped(std::make_unique<HalfCheetahEnv>(Vel()), 20);
  const auto& env = dynamic_cast<const HalfCheetahEnv&>(wrapped.inner());
  const auto* source = FindThroughWrappers<sim::SceneSource>(wrapped);
  ASSERT_EQ(source, &env);
  EXPECT_EQ(source->ActiveScene().model, env.model());
  EXPECT_EQ(source->ActiveScene().data, env.data());
  EXPECT_EQ(source->default_camera(), "track");
  EXPECT_EQ(FindThroughWrappers<ScriptedPolicySource>(wrapped), nullptr);  // it has none

  const std::filesystem::path path =
      test_support::ScratchDir("half_cheetah", "xml", /*create=*/true) / "half_cheetah.xml";
  source->SaveSceneXml(path.string());
  const sim::ModelPtr loaded = sim::LoadModelFromFile(path.string());
  const mjModel* own = env.model();
  EXPECT_EQ(loaded->nq, own->nq);
  EXPECT_EQ(loaded->nu, own->nu);
  EXPECT_EQ(loaded->nbody, own->nbody);
  EXPECT_EQ(loaded->ncam, own->ncam);
  const sim::DataPtr a = sim::MakeData(loaded.get());
  const sim::DataPtr b = sim::MakeData(own);
  for (int t = 0; t < 50; ++t) {
    for (int i = 0; i < own->nu; ++i) a->ctrl[i] = b->ctrl[i] = std::sin(0.3 * t + i);
    mj_step(loaded.get(), a.get());
    mj_step(own, b.get());
  }
  for (int i = 0; i < own->nq; ++i) EXPECT_EQ(a->qpos[i], b->qpos[i]) << i;
}

#ifdef MANYWORLDS_HAS_RENDER
// The camera "track" sees the cheetah: its warm body colour (red above
// blue) fills part of the image, the cool floor (blue above red) another.
TEST(HalfCheetahTest, RendersFromItsTrackingCamera) {
  HalfCheetahEnv env(Dir());
  env.Reset();
  for (int t = 0; t < 20; ++t) env.Step(std::vector<float>{1, -1, 1, -1, 1, -1});
  const sim::Scene scene = env.ActiveScene();
  constexpr int kW = 64, kH = 48;
  sim::Renderer renderer(kW, kH);
  const std::vector<uint8_t> rgb = renderer.Render(scene.model, scene.data, env.default_camera());
  int body = 0, floor = 0;
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
    body += rgb[i] > rgb[i + 2] + 30;
    floor += rgb[i + 2] > rgb[i] + 10;
  }
  EXPECT_GT(body, kW * kH / 50) << "body pixels";
  EXPECT_GT(floor, kW * kH / 10) << "floor pixels";
}
#endif  // MANYWORLDS_HAS_RENDER

}  // namespace
}  // namespace manyworlds::locomotion
