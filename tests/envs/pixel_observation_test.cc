// Pixel observations through the registry (obs=pixels): shapes, agreement with a direct render,
// frame stacking and action repeat against hand-stepped sequences, the batched executor at
// several thread counts, and the errors for envs and builds that cannot render.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/env_checker.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/executor.h"
#include "manyworlds/envs/all.h"

#ifdef MANYWORLDS_HAS_RENDER
#include <mujoco/mujoco.h>

#include "manyworlds/sim/render.h"
#endif

namespace manyworlds {
namespace {

using Json = nlohmann::json;

std::vector<float> Action(const Env& env, float value) {
  return std::vector<float>(env.spec().action_space.flat_size(), value);
}

TEST(PixelOptionsTest, ClassicEnvsHaveNoSceneToRender) {
  try {
    Make("cartpole", {{"obs", "pixels"}});
    FAIL() << "cartpole rendered pixels";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("has no MuJoCo scene"), std::string::npos) << e.what();
  }
}

TEST(PixelOptionsTest, PixelSettingsWithoutPixelsAreRefused) {
  EXPECT_THROW(Make("reach", {{"camera", "top"}}), ConfigError);
  EXPECT_THROW(Make("reach", {{"pixel_width", 64}}), ConfigError);
  EXPECT_THROW(Make("reach", {{"obs", "image"}}), ConfigError);
  EXPECT_THROW(Make("reach", {{"obs", "pixels"}, {"pixel_width", 0}}), ConfigError);
  EXPECT_THROW(Make("reach", {{"obs", "pixels"}, {"pixel_height", 5000}}), ConfigError);
}

TEST(PixelOptionsTest, StateEnvsHaveNoPixels) {
  auto env = Make("reach");
  EXPECT_EQ(env->spec().pixel_space.flat_size(), 0);
  EXPECT_TRUE(env->Reset().pixels.empty());
}

#ifdef MANYWORLDS_HAS_RENDER

TEST(PixelObservationTest, ShapeIsChannelsFirstAndTheStateStaysTheState) {
  auto pixels = Make("reach", {{"obs", "pixels"}, {"pixel_width", 48}, {"pixel_height", 32}});
  auto state = Make("reach");
  EXPECT_EQ(pixels->spec().pixel_space.shape(), (std::vector<int64_t>{3, 32, 48}));
  EXPECT_EQ(pixels->spec().env_obs_space, state->spec().env_obs_space);
  pixels->Seed(3);
  state->Seed(3);
  const Observation a = pixels->Reset();
  const Observation b = state->Reset();
  EXPECT_EQ(a.env_obs, b.env_obs);
  ASSERT_EQ(a.pixels.size(), 3u * 32 * 48);
  for (int step = 0; step < 5; ++step) {
    const StepResult ra = pixels->Step(Action(*pixels, 0.7f));
    const StepResult rb = state->Step(Action(*state, 0.7f));
    EXPECT_EQ(ra.obs.env_obs, rb.obs.env_obs);
    EXPECT_EQ(ra.reward, rb.reward);
  }
}

class PixelQualityTest : public ::testing::TestWithParam<std::string> {};

TEST_P(PixelQualityTest, FramesAreTheSceneRenderedFromTheCamera) {
  auto env = Make("reach", {{"obs", "pixels"}, {"camera", "top"}, {"pixel_width", 40},
                            {"pixel_height", 30}, {"pixel_quality", GetParam()}});
  env->Reset();
  const StepResult r = env->Step(Action(*env, 1.0f));
  sim::Renderer renderer(40, 30, GetParam() == "full" ? sim::RenderQuality::kFull
                                                      : sim::RenderQuality::kFast);
  const MujocoScene scene = ActiveMujocoScene(*env);
  const std::vector<uint8_t> rgb = renderer.Render(
      reinterpret_cast<const mjModel*>(scene.model), reinterpret_cast<const mjData*>(scene.data),
      "top");
  const size_t plane = 40 * 30;
  for (size_t p = 0; p < plane; ++p) {
    for (size_t c = 0; c < 3; ++c) ASSERT_EQ(r.obs.pixels[c * plane + p], rgb[3 * p + c]) << p;
  }
  // an image, not a blank: the table, the arm and the floor differ
  int distinct = 0;
  for (size_t p = 1; p < plane; ++p) distinct += r.obs.pixels[p] != r.obs.pixels[0];
  EXPECT_GT(distinct, static_cast<int>(plane / 10));
}

INSTANTIATE_TEST_SUITE_P(Qualities, PixelQualityTest, ::testing::Values("fast", "full"));

TEST(PixelObservationTest, UnknownCameraListsTheAllowedOnes) {
  try {
    Make("reach", {{"obs", "pixels"}, {"camera", "fronnt"}})->Reset();
    FAIL() << "an unknown camera rendered";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("front"), std::string::npos) << e.what();
  }
}

// A moving arm: the frames of consecutive steps differ.
std::vector<std::vector<uint8_t>> HandStepped(Env& env, int steps) {
  std::vector<std::vector<uint8_t>> frames{env.Reset().pixels};
  for (int k = 0; k < steps; ++k) frames.push_back(env.Step(Action(env, k % 2 ? -1.0f : 1.0f)).obs.pixels);
  return frames;
}

TEST(PixelObservationTest, FrameStackStacksFramesOldestFirst) {
  const Json base = {{"obs", "pixels"}, {"pixel_width", 24}, {"pixel_height", 24}};
  Json stacked_options = base;
  stacked_options["frame_stack"] = 3;
  auto single = Make("reach", base);
  auto stacked = Make("reach", stacked_options);
  EXPECT_EQ(stacked->spec().pixel_space.shape(), (std::vector<int64_t>{9, 24, 24}));
  EXPECT_EQ(stacked->spec().env_obs_space, single->spec().env_obs_space);  // the state: unstacked
  const std::vector<std::vector<uint8_t>> frames = HandStepped(*single, 4);
  ASSERT_NE(frames[1], frames[2]);
  const size_t f = frames[0].size();
  std::vector<std::vector<uint8_t>> got{stacked->Reset().pixels};
  for (int k = 0; k < 4; ++k) got.push_back(stacked->Step(Action(*stacked, k % 2 ? -1.0f : 1.0f)).obs.pixels);
  for (int t = 0; t <= 4; ++t) {
    for (int slot = 0; slot < 3; ++slot) {
      const int source = std::max(0, t - 2 + slot);  // oldest first; the reset frame repeats
      const std::vector<uint8_t> part(got[t].begin() + slot * f, got[t].begin() + (slot + 1) * f);
      EXPECT_EQ(part, frames[source]) << "step " << t << " slot " << slot;
    }
  }
}

TEST(PixelObservationTest, ActionRepeatRendersAfterTheRepeatedSteps) {
  const Json base = {{"obs", "pixels"}, {"pixel_width", 24}, {"pixel_height", 24}};
  Json repeated_options = base;
  repeated_options["action_repeat"] = 2;
  auto single = Make("reach", base);
  auto repeated = Make("reach", repeated_options);
  single->Reset();
  repeated->Reset();
  for (int k = 0; k < 3; ++k) {
    single->Step(Action(*single, 0.5f));
    const StepResult a = single->Step(Action(*single, 0.5f));
    const StepResult b = repeated->Step(Action(*repeated, 0.5f));
    EXPECT_EQ(a.obs.pixels, b.obs.pixels) << "agent step " << k;
    EXPECT_EQ(a.obs.env_obs, b.obs.env_obs);
  }
}

// Pixels through the executor: the same at 1 and 3 threads, equal to each env stepped alone, and
// the envs of one task share one set of GL resources per thread.
TEST(PixelObservationTest, ExecutorPixelsDoNotDependOnThreads) {
  const Json options = {{"obs", "pixels"}, {"pixel_width", 32}, {"pixel_height", 32}};
  const std::vector<std::string> ids = {"reach", "push", "reach", "window-open"};
  auto run = [&](int threads) {
    std::vector<std::unique_ptr<Env>> envs;
    for (const auto& id : ids) envs.push_back(Make(id, options));
    BatchedExecutor exec(std::move(envs), {.num_threads = threads});
    exec.Seed(5, 6);
    exec.Reset();
    std::vector<float> actions(ids.size() * exec.action_size());
    for (size_t i = 0; i < actions.size(); ++i) actions[i] = (i % 3) * 0.5f - 0.5f;
    for (int k = 0; k < 3; ++k) exec.Step(actions);
    return std::vector<uint8_t>(exec.pixels().begin(), exec.pixels().end());
  };
  const std::vector<uint8_t> one = run(1);
  ASSERT_EQ(one.size(), ids.size() * 3 * 32 * 32);
  EXPECT_EQ(run(3), one);
  // env 1 (push) alone, with the seeds the executor gave it
  auto alone = Make("push", options);
  alone->Seed(MixSeed(5, 1));
  alone->SeedTask(MixSeed(6, 1));
  alone->Reset();
  std::vector<float> action(alone->spec().action_space.flat_size());
  StepResult r;
  for (int k = 0; k < 3; ++k) {
    for (size_t j = 0; j < action.size(); ++j) {
      action[j] = ((action.size() + j) % 3) * 0.5f - 0.5f;
    }
    r = alone->Step(action);
  }
  const size_t frame = 3 * 32 * 32;
  EXPECT_EQ(std::vector<uint8_t>(one.begin() + frame, one.begin() + 2 * frame), r.obs.pixels);
}

TEST(PixelObservationTest, ModelRenderKeyTellsTasksApart) {
  auto a = Make("reach");
  auto b = Make("reach");
  auto c = Make("push");
  for (Env* env : {a.get(), b.get(), c.get()}) env->Reset();
  auto key = [](const Env& env) {
    return sim::ModelRenderKey(reinterpret_cast<const mjModel*>(ActiveMujocoScene(env).model));
  };
  EXPECT_EQ(key(*a), key(*b));
  EXPECT_NE(key(*a), key(*c));
}

TEST(PixelObservationTest, PassesTheEnvChecker) {
  CheckOptions options;
  options.steps = 40;
  const CheckReport report = CheckEnv(
      [] { return Make("half-cheetah-vel", {{"obs", "pixels"}, {"frame_stack", 2}}); }, options);
  EXPECT_TRUE(report.ok()) << report.ToString();
}

#endif  // MANYWORLDS_HAS_RENDER

}  // namespace
}  // namespace manyworlds
