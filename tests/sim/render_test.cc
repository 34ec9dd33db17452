// Offscreen rendering through OSMesa. These tests never skip: a machine on
// which no OSMesa context can be made fails them.
#include <gtest/gtest.h>

#ifdef MANYWORLDS_HAS_RENDER

#include <cstdint>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/sim/model.h"
#include "manyworlds/sim/render.h"

namespace manyworlds::sim {
namespace {

// A red box at the origin on a blue floor; the camera "above" looks straight
// down at it. The box spans x, y in [-0.1, 0.1], so from 1 m with a 45
// degree field of view it fills the middle fifth of the image.
constexpr char kScene[] = R"(
<mujoco model="box">
  <visual><headlight ambient="0.6 0.6 0.6" diffuse="0.3 0.3 0.3" specular="0 0 0"/></visual>
  <worldbody>
    <geom name="floor" type="plane" pos="0 0 -0.1" size="0.4 0.4 0.01" rgba="0 0 1 1"/>
    <body name="box" pos="0 0 0">
      <geom type="box" size="0.1 0.1 0.1" rgba="1 0 0 1"/>
    </body>
    <camera name="above" pos="0 0 1.1" xyaxes="1 0 0 0 1 0" fovy="45"/>
  </worldbody>
</mujoco>)";

struct Pixel {
  int r, g, b;
};

Pixel At(const std::vector<uint8_t>& rgb, int width, int x, int y) {
  const size_t i = (static_cast<size_t>(y) * width + x) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

bool IsRed(Pixel p) { return p.r > 100 && p.g < 40 && p.b < 40; }
bool IsBlue(Pixel p) { return p.b > 100 && p.r < 40 && p.g < 40; }
bool IsBlack(Pixel p) { return p.r + p.g + p.b < 30; }

// One renderer for all tests: making an OSMesa context and compiling
// llvmpipe's shaders is the slow part (~0.4 s). It is made in the first
// test's SetUp, not in SetUpTestSuite: GoogleTest reports the tests of a
// suite whose SetUpTestSuite threw as skipped, and these must fail.
constexpr int kW = 96, kH = 64;

Renderer& SharedRenderer() {
  static Renderer* renderer = new Renderer(kW, kH);  // retried by each test if it throws
  return *renderer;
}

class RenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    renderer_ = &SharedRenderer();  // throws (the test fails) without OSMesa
    renderer_->ForgetModel();       // the last test's model is gone
    model_ = LoadModelFromString(kScene);
    data_ = MakeData(model_.get());
    mj_forward(model_.get(), data_.get());
  }

  Renderer* renderer_ = nullptr;
  ModelPtr model_;
  DataPtr data_;
};

TEST_F(RenderTest, BoxAppearsWhereTheCameraLooks) {
  const std::vector<uint8_t> rgb = renderer_->Render(model_.get(), data_.get(), "above");
  ASSERT_EQ(rgb.size(), size_t{kW * kH * 3});

  // not blank: several colours
  int red = 0, blue = 0, black = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const Pixel p = At(rgb, kW, x, y);
      red += IsRed(p);
      blue += IsBlue(p);
      black += IsBlack(p);
    }
  }
  EXPECT_GT(red, 0);
  EXPECT_GT(blue, 0);
  EXPECT_GT(black, 0);
  // the box in the middle, floor around it, background in the corners
  EXPECT_TRUE(IsRed(At(rgb, kW, kW / 2, kH / 2)));
  EXPECT_TRUE(IsBlue(At(rgb, kW, kW / 2, kH / 2 + 18)));
  EXPECT_TRUE(IsBlack(At(rgb, kW, 1, 1)));
  EXPECT_TRUE(IsBlack(At(rgb, kW, kW - 2, kH - 2)));
}

TEST_F(RenderTest, ImageIsTopRowFirst) {
  // move the box towards +y, which is up in the image of camera "above"
  ModelPtr moved(mj_copyModel(nullptr, model_.get()));
  moved->body_pos[3 * 1 + 1] = 0.25;
  DataPtr data = MakeData(moved.get());
  mj_forward(moved.get(), data.get());
  const std::vector<uint8_t> rgb = renderer_->Render(moved.get(), data.get(), "above");
  EXPECT_TRUE(IsRed(At(rgb, kW, kW / 2, 8)));        // near the top
  EXPECT_FALSE(IsRed(At(rgb, kW, kW / 2, kH - 8)));  // not near the bottom
  renderer_->ForgetModel();
}

TEST_F(RenderTest, PresetsRenderAndSwitchingModelsWorks) {
  for (const char* camera : {"front", "top", "side"}) {
    const std::vector<uint8_t> rgb = renderer_->Render(model_.get(), data_.get(), camera);
    int red = 0;
    for (size_t i = 0; i + 2 < rgb.size(); i += 3) red += rgb[i] > 100 && rgb[i + 1] < 40;
    EXPECT_GT(red, 0) << camera;
  }
  // another model through the same renderer, then the first one again
  ModelPtr other = LoadModelFromString(
      R"(<mujoco><visual><headlight ambient="0.5 0.5 0.5"/></visual>
          <worldbody><geom type="sphere" size="0.2" rgba="0 1 0 1"/></worldbody></mujoco>)");
  DataPtr other_data = MakeData(other.get());
  mj_forward(other.get(), other_data.get());
  const std::vector<uint8_t> green = renderer_->Render(other.get(), other_data.get(), "front");
  const Pixel centre = At(green, kW, kW / 2, kH / 2);
  EXPECT_GT(centre.g, 80);
  EXPECT_GT(centre.g, 2 * centre.r);
  const std::vector<uint8_t> rgb = renderer_->Render(model_.get(), data_.get(), "above");
  EXPECT_TRUE(IsRed(At(rgb, kW, kW / 2, kH / 2)));
}

TEST_F(RenderTest, CallerDataIsNotTouched) {
  // mjv_updateScene uses the stack of the mjData it gets: the renderer
  // gives it a copy
  const auto* buffer = static_cast<const uint8_t*>(data_->buffer);
  const auto* stack = reinterpret_cast<const uint8_t*>(data_->stack);
  const std::vector<uint8_t> buffer_before(buffer, buffer + data_->nbuffer);
  const std::vector<uint8_t> stack_before(stack, stack + data_->nstack * sizeof(mjtNum));
  const int pstack = data_->pstack;
  renderer_->Render(model_.get(), data_.get(), "front");
  EXPECT_EQ(std::vector<uint8_t>(buffer, buffer + data_->nbuffer), buffer_before);
  EXPECT_EQ(std::vector<uint8_t>(stack, stack + data_->nstack * sizeof(mjtNum)), stack_before);
  EXPECT_EQ(data_->pstack, pstack);
}

TEST_F(RenderTest, BadCameraNameThrowsAndListsAllowedNames) {
  try {
    renderer_->Render(model_.get(), data_.get(), "abov");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("abov"), std::string::npos) << what;
    for (const char* name : {"front", "top", "side", "gripper", "above"}) {
      EXPECT_NE(what.find(name), std::string::npos) << what;
    }
  }
  // "gripper" follows the body "hand", which this model lacks
  EXPECT_THROW(renderer_->Render(model_.get(), data_.get(), "gripper"), ConfigError);
}

TEST_F(RenderTest, WrongBufferSizeThrows) {
  std::vector<uint8_t> small(kW * kH * 3 - 1);
  EXPECT_THROW(renderer_->Render(model_.get(), data_.get(), "front", small), Error);
}

TEST(RendererTest, BadSizeThrows) {
  EXPECT_THROW(Renderer(0, 10), ConfigError);
  EXPECT_THROW(Renderer(10, -1), ConfigError);
  EXPECT_THROW(Renderer(Renderer::kMaxSize + 1, 10), ConfigError);
}

}  // namespace
}  // namespace manyworlds::sim

#else  // !MANYWORLDS_HAS_RENDER

TEST(RenderTest, BuiltWithOsmesa) {
  FAIL() << "manyworlds was built without OSMesa (libosmesa6-dev), so it cannot render";
}

#endif  // MANYWORLDS_HAS_RENDER
