#include "manyworlds/core/space.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

TEST(SpaceTest, BoxContainsAndDescribes) {
  Space box = Space::Box(-1.0f, 1.0f, {4});
  EXPECT_EQ(box.flat_size(), 4);
  EXPECT_TRUE(box.Contains(std::vector<float>{0, 1, -1, 0.5f}));
  EXPECT_FALSE(box.Contains(std::vector<float>{0, 1.01f, 0, 0}));
  EXPECT_FALSE(box.Contains(std::vector<float>{0, 0, 0}));
  EXPECT_FALSE(box.Contains(std::vector<float>{0, NAN, 0, 0}));
  EXPECT_EQ(box.ToString(), "Box(-1.0, 1.0, (4,), float32)");
}

TEST(SpaceTest, DiscreteContainsOnlyIntegersInRange) {
  Space d = Space::Discrete(3);
  EXPECT_EQ(d.flat_size(), 1);
  EXPECT_TRUE(d.Contains(std::vector<float>{2}));
  EXPECT_FALSE(d.Contains(std::vector<float>{3}));
  EXPECT_FALSE(d.Contains(std::vector<float>{-1}));
  EXPECT_FALSE(d.Contains(std::vector<float>{0.5f}));
  EXPECT_EQ(d.ToString(), "Discrete(3)");
}

TEST(SpaceTest, SamplesLieInsideEvenWithInfiniteBounds) {
  const float inf = std::numeric_limits<float>::infinity();
  Space box = Space::Box({-inf, 0.0f, -2.0f, -inf}, {inf, inf, 2.0f, 1.0f}, {2, 2});
  Rng rng(7);
  for (int i = 0; i < 1000; ++i) EXPECT_TRUE(box.Contains(box.Sample(rng)));
  Space d = Space::Discrete(5);
  std::vector<int> counts(5);
  for (int i = 0; i < 5000; ++i) counts[static_cast<int>(d.Sample(rng)[0])]++;
  for (int c : counts) EXPECT_GT(c, 800);
}

TEST(SpaceTest, ClipMovesIntoBounds) {
  Space box = Space::Box({-1.0f, 0.0f}, {1.0f, 2.0f}, {2});
  std::vector<float> v{-3.0f, 5.0f};
  box.Clip(v);
  EXPECT_EQ(v, (std::vector<float>{-1.0f, 2.0f}));
}

TEST(SpaceTest, RejectsInvalidDefinitions) {
  EXPECT_THROW(Space::Discrete(0), ConfigError);
  EXPECT_THROW(Space::Box({1.0f}, {0.0f}, {1}), ConfigError);
  EXPECT_THROW(Space::Box({0.0f, 0.0f}, {1.0f}, {2}), ConfigError);
}

TEST(SpaceTest, JsonDescribesBounds) {
  const auto json = Space::Box(-1.0f, 1.0f, {2}).ToJson();
  EXPECT_EQ(json["type"], "Box");
  EXPECT_EQ(json["shape"], nlohmann::json::array({2}));
  EXPECT_EQ(Space::Discrete(4).ToJson()["n"], 4);
}

}  // namespace
}  // namespace manyworlds
