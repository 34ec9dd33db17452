// The box world's generator: determinism, the placement rules on many
// seeds, JSON round trips, and one test per bad parameter (one-line
// ConfigErrors naming the parameter and its range).
#include "manyworlds/boxworld/world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include "manyworlds/boxworld/world_model.h"
#include "manyworlds/core/error.h"

namespace manyworlds::boxworld {
namespace {

WorldDistribution Broad() {
  WorldDistribution d;
  d.floor_size = {4.0, 8.0};
  d.num_boxes = {1, 6};
  d.box_shapes = {Shape::kBox, Shape::kCylinder, Shape::kSphere};
  d.box_size = {0.08, 0.3};
  d.box_mass = {0.02, 0.5};
  d.box_friction = {0.05, 0.5};
  d.random_colors = true;
  return d;
}

// The error text of `f`, which must throw ConfigError.
std::string ConfigErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no ConfigError)";
}

TEST(WorldTest, AWorldIsAPureFunctionOfTheDistributionAndTheSeed) {
  const WorldDistribution d = Broad();
  for (uint64_t seed : {0u, 1u, 99u}) {
    EXPECT_EQ(GenerateWorld(d, seed), GenerateWorld(d, seed));
    EXPECT_EQ(ToJson(GenerateWorld(d, seed)).dump(), ToJson(GenerateWorld(d, seed)).dump());
  }
  EXPECT_NE(GenerateWorld(d, 1), GenerateWorld(d, 2));
  // the same model text too
  EXPECT_EQ(WorldMjcf(GenerateWorld(d, 5)).ToXml(), WorldMjcf(GenerateWorld(d, 5)).ToXml());
}

TEST(WorldTest, GeneratedWorldsKeepThePlacementRules) {
  const WorldDistribution d = Broad();
  int shapes_seen[3] = {0, 0, 0};
  for (uint64_t seed = 0; seed < 500; ++seed) {
    const WorldParams w = GenerateWorld(d, seed);
    ASSERT_NO_THROW(Validate(w)) << seed;
    ASSERT_GE(w.floor_size, 4.0);
    ASSERT_LE(w.floor_size, 8.0);
    ASSERT_GE(w.boxes.size(), 1u);
    ASSERT_LE(w.boxes.size(), 6u);
    ASSERT_DOUBLE_EQ(w.success_radius, 0.2 * w.floor_size);
    const double half = w.floor_size / 2;
    for (const BoxParams& b : w.boxes) {
      ++shapes_seen[static_cast<int>(b.shape)];
      const double r = FootprintRadius(b);
      // inside the walls with the clearance, away from the agent and target
      ASSERT_LE(std::abs(b.start[0]), half - r - kPlacementClearance + 1e-12);
      ASSERT_LE(std::abs(b.start[1]), half - r - kPlacementClearance + 1e-12);
      ASSERT_GE(std::hypot(b.start[0] - w.agent_start[0], b.start[1] - w.agent_start[1]),
                r + w.agent_radius + kPlacementClearance);
      ASSERT_GE(std::hypot(b.start[0] - w.target[0], b.start[1] - w.target[1]),
                w.min_target_distance);
    }
    for (size_t i = 0; i < w.boxes.size(); ++i) {
      for (size_t j = 0; j < i; ++j) {
        const double d_ij = std::hypot(w.boxes[i].start[0] - w.boxes[j].start[0],
                                       w.boxes[i].start[1] - w.boxes[j].start[1]);
        ASSERT_GE(d_ij, FootprintRadius(w.boxes[i]) + FootprintRadius(w.boxes[j]) +
                            kPlacementClearance);
      }
    }
    ASSERT_GE(std::hypot(w.target[0] - w.agent_start[0], w.target[1] - w.agent_start[1]),
              w.min_target_distance);
    ASSERT_LE(std::abs(w.target[0]), half - w.success_radius);
  }
  for (int count : shapes_seen) EXPECT_GT(count, 100);
}

TEST(WorldTest, AFixedLayoutSeedVariesOnlyTheTarget) {
  WorldDistribution d = Broad();
  d.layout_seed = 7;
  Rng rng(3);
  const WorldParams first = d.Sample(rng);
  const WorldParams second = d.Sample(rng);
  EXPECT_NE(first.target, second.target);
  WorldParams same_layout = second;
  same_layout.target = first.target;
  EXPECT_EQ(first, same_layout);
  EXPECT_TRUE(SameStructure(first, second));
  EXPECT_FALSE(SameStructure(first, GenerateWorld(Broad(), 1)));
}

TEST(WorldTest, JsonRoundTripsExactlyAndIsValidated) {
  const WorldParams w = GenerateWorld(Broad(), 11);
  const std::string text = ToJson(w).dump();
  EXPECT_EQ(WorldFromJson(nlohmann::json::parse(text)), w);

  nlohmann::json missing = ToJson(w);
  missing.erase("floor_size");
  EXPECT_EQ(ConfigErrorOf([&] { WorldFromJson(missing); }), "box world: floor_size is missing");
  nlohmann::json extra = ToJson(w);
  extra["gravity"] = 1;
  EXPECT_NE(ConfigErrorOf([&] { WorldFromJson(extra); }).find("gravity is not a world parameter"),
            std::string::npos);
  nlohmann::json shape = ToJson(w);
  shape["boxes"][0]["shape"] = "cube";
  EXPECT_EQ(ConfigErrorOf([&] { WorldFromJson(shape); }),
            "box world: boxes[0].shape must be box, cylinder or sphere, got 'cube'");
  nlohmann::json type = ToJson(w);
  type["target"] = "middle";
  EXPECT_NE(ConfigErrorOf([&] { WorldFromJson(type); }).find("target must be an array of 2"),
            std::string::npos);
  nlohmann::json negative = ToJson(w);
  negative["boxes"][0]["size"] = -0.2;
  EXPECT_NE(ConfigErrorOf([&] { WorldFromJson(negative); }).find("boxes[0].size must be in"),
            std::string::npos);
}

// A valid hand-made world to break one field at a time.
WorldParams Base() {
  WorldParams w;  // 5 m floor, success radius 1, min target distance 1
  w.agent_start = {-1.5, -1.5};
  w.target = {1.0, 1.0};
  BoxParams a;
  a.start = {0.0, -1.5};
  BoxParams b;
  b.start = {-1.5, 0.5};
  w.boxes = {a, b};
  return w;
}

struct BadCase {
  const char* name;
  std::function<void(WorldParams&)> change;
  const char* message;  // the whole ConfigError text
};

TEST(WorldTest, EveryBadParameterIsAOneLineErrorNamingItAndItsRange) {
  ASSERT_NO_THROW(Validate(Base()));
  const BadCase cases[] = {
      {"negative floor", [](WorldParams& w) { w.floor_size = -5; },
       "box world: floor_size must be in [1, 100], got -5"},
      {"NaN floor", [](WorldParams& w) { w.floor_size = std::nan(""); },
       "box world: floor_size must be in [1, 100], got nan"},
      {"wall", [](WorldParams& w) { w.wall_height = 0; },
       "box world: wall_height must be in [0.05, 10], got 0"},
      {"agent radius", [](WorldParams& w) { w.agent_radius = 2; },
       "box world: agent_radius must be in [0.01, 1.25] (up to floor_size / 4), got 2"},
      {"agent force", [](WorldParams& w) { w.agent_force = 0; },
       "box world: agent_force must be in (0, 50], got 0"},
      {"agent torque", [](WorldParams& w) { w.agent_torque = -1; },
       "box world: agent_torque must be in (0, 10], got -1"},
      {"success radius", [](WorldParams& w) { w.success_radius = std::nan(""); },
       "box world: success_radius must be in [0.01, 1.25] (up to floor_size / 4), got nan"},
      {"min target distance", [](WorldParams& w) { w.min_target_distance = 0.5; },
       "box world: min_target_distance must be in [1, 2.12132] (success_radius to (floor_size - "
       "2 success_radius) / sqrt(2); a larger floor allows more), got 0.5"},
      {"floor too small for the target distance",
       [](WorldParams& w) {
         w.floor_size = 1.2;
         w.success_radius = 0.25;
         w.min_target_distance = 0.6;
         w.agent_radius = 0.1;
         w.boxes.clear();
       },
       "box world: min_target_distance must be in [0.25, 0.494975] (success_radius to "
       "(floor_size - 2 success_radius) / sqrt(2); a larger floor allows more), got 0.6"},
      {"negative box size", [](WorldParams& w) { w.boxes[1].size = -0.1; },
       "box world: boxes[1].size must be in [0.01, 1.25] (up to floor_size / 4), got -0.1"},
      {"box mass", [](WorldParams& w) { w.boxes[0].mass = 0; },
       "box world: boxes[0].mass must be in [0.001, 1000], got 0"},
      {"box friction", [](WorldParams& w) { w.boxes[0].friction = -1; },
       "box world: boxes[0].friction must be in [0, 10], got -1"},
      {"box colour", [](WorldParams& w) { w.boxes[1].rgba[3] = 2; },
       "box world: boxes[1].rgba[3] must be in [0, 1], got 2"},
      {"box yaw", [](WorldParams& w) { w.boxes[1].start_yaw = 4; },
       "box world: boxes[1].start_yaw must be in [-3.14159, 3.14159], got 4"},
      {"more boxes than fit",
       [](WorldParams& w) {
         BoxParams big;
         big.size = 0.5;
         w.boxes.assign(12, big);
       },
       "box world: num_boxes must be in [0, 5] on a 5 m floor with boxes of footprint radius up "
       "to 0.707107 m (their footprints may cover at most 50% of the floor), got 12"},
      {"more boxes than the limit",
       [](WorldParams& w) {
         BoxParams tiny;
         tiny.size = 0.01;
         w.boxes.assign(65, tiny);
       },
       "box world: num_boxes must be in [0, 64], got 65"},
      {"agent outside", [](WorldParams& w) { w.agent_start[0] = 2.4; },
       "box world: agent_start[0] must be in [-2.35, 2.35] (inside the walls: floor_size / 2 - "
       "footprint radius 0.15), got 2.4"},
      {"box outside", [](WorldParams& w) { w.boxes[0].start[1] = -2.45; },
       "box world: boxes[0].start[1] must be in [-2.32322, 2.32322] (inside the walls: "
       "floor_size / 2 - footprint radius 0.176777), got -2.45"},
      {"overlap", [](WorldParams& w) { w.boxes[1].start = {0.1, -1.4}; },
       "box world: boxes[1].start must be at least 0.353553 m (the sum of footprint radii) from "
       "boxes[0].start, got 0.141421 m"},
      {"target outside", [](WorldParams& w) { w.target[1] = 1.6; },
       "box world: target[1] must be in [-1.5, 1.5] (floor_size / 2 - success_radius), got 1.6"},
      {"target too close", [](WorldParams& w) { w.target = {-1.0, 0.5}; },
       "box world: target must be at least min_target_distance = 1 m from boxes[1].start, got "
       "0.5 m"},
  };
  for (const BadCase& c : cases) {
    WorldParams w = Base();
    c.change(w);
    const std::string message = ConfigErrorOf([&] { Validate(w); });
    EXPECT_EQ(message, c.message) << c.name;
    EXPECT_EQ(message.find('\n'), std::string::npos) << c.name;
  }
}

TEST(WorldTest, BadDistributionsNameTheOption) {
  struct Case {
    std::function<void(WorldDistribution&)> change;
    const char* starts_with;
  };
  const Case cases[] = {
      {[](WorldDistribution& d) { d.floor_size = {-2, 5}; },
       "box world: floor_size (min) must be in [1, 100], got -2"},
      {[](WorldDistribution& d) { d.floor_size = {6, 5}; },
       "box world: floor_size: min 6 exceeds max 5"},
      {[](WorldDistribution& d) { d.box_size = {-0.1, 0.2}; },
       "box world: box_size (min) must be in [0.01, 1.25]"},
      {[](WorldDistribution& d) { d.box_mass = {0.1, std::nan("")}; },
       "box world: box_mass (max) must be in [0.001, 1000]"},
      {[](WorldDistribution& d) { d.num_boxes = {1, 70}; },
       "box world: num_boxes must be in [0, 64]"},
      {[](WorldDistribution& d) {
         d.num_boxes = {1, 30};
         d.box_size = {0.1, 0.4};
       },
       "box world: num_boxes must be in [0, 9] on a 5 m floor"},
      {[](WorldDistribution& d) { d.box_shapes.clear(); }, "box world: box_shapes must name"},
      {[](WorldDistribution& d) { d.min_target_distance_ratio = 0.6; },
       "box world: min_target_distance_ratio must be in [0.2, 0.424264]"},
      {[](WorldDistribution& d) { d.success_radius_ratio = 0.3; },
       "box world: success_radius_ratio must be in [0.002, 0.25]"},
      {[](WorldDistribution& d) { d.layout_seed = -4; }, "box world: layout_seed must be -1"},
      {[](WorldDistribution& d) { d.starts.box_start_gap = -0.5; },
       "box world: box_start_gap must be in [0, 5] (-1 (anywhere) or a gap in m up to "
       "floor_size), got -0.5"},
      {[](WorldDistribution& d) { d.starts.box_start_gap = std::nan(""); },
       "box world: box_start_gap must be in [0, 5]"},
  };
  for (const Case& c : cases) {
    WorldDistribution d;
    c.change(d);
    const std::string message = ConfigErrorOf([&] { d.Validate(); });
    EXPECT_EQ(message.rfind(c.starts_with, 0), 0u) << message;
  }
}

TEST(WorldTest, PlacementThatCannotSucceedIsAClearError) {
  // within the fill rule but every target spot is too close to a box
  WorldParams w;
  w.floor_size = 2.0;
  w.success_radius = 0.2;
  w.min_target_distance = 0.98;
  w.agent_radius = 0.05;
  BoxParams b;
  b.size = 0.05;
  w.boxes.assign(6, b);
  Rng rng(1);
  PlaceObjects(w, rng);
  const std::string message = ConfigErrorOf([&] { PlaceTarget(w, rng); });
  EXPECT_EQ(message.rfind("box world: could not place the target at least min_target_distance", 0),
            0u)
      << message;
}

TEST(WorldTest, BoxStartGapStartsEveryBoxNextToTheAgent) {
  WorldDistribution d = Broad();
  d.num_boxes = {1, 3};
  d.starts.box_start_gap = 0.1;
  double closest_to_wall = 1e9;
  for (uint64_t seed = 0; seed < 300; ++seed) {
    const WorldParams w = GenerateWorld(d, seed);
    ASSERT_NO_THROW(Validate(w)) << seed;
    const double half = w.floor_size / 2;
    for (const BoxParams& b : w.boxes) {
      const double touching = FootprintRadius(b) + w.agent_radius + kPlacementClearance;
      const double gap =
          std::hypot(b.start[0] - w.agent_start[0], b.start[1] - w.agent_start[1]) - touching;
      ASSERT_GE(gap, -1e-12) << seed;
      ASSERT_LE(gap, 0.1 + 1e-12) << seed;
      closest_to_wall = std::min(closest_to_wall, half - std::abs(b.start[0]));
    }
  }
  // the agent still starts anywhere: some boxes end up beside a wall
  EXPECT_LT(closest_to_wall, 0.5);
  // boxes far from the agent without the option
  d.starts.box_start_gap = -1;
  int far = 0;
  for (uint64_t seed = 0; seed < 50; ++seed) {
    const WorldParams w = GenerateWorld(d, seed);
    const BoxParams& b = w.boxes.front();
    far += std::hypot(b.start[0] - w.agent_start[0], b.start[1] - w.agent_start[1]) > 1.0;
  }
  EXPECT_GT(far, 25);
}

TEST(WorldTest, TheCornerLayoutPutsTheBoxesInFrontOfTheAgent) {
  // the study's code: agent 0.55 m from two walls, its cube touching it on
  // the diagonal toward the room
  WorldDistribution d;
  d.starts = {.agent_in_corner = true, .box_start_gap = 0.1};
  int corners[4] = {0, 0, 0, 0};
  for (uint64_t seed = 0; seed < 400; ++seed) {
    const WorldParams w = GenerateWorld(d, seed);
    ASSERT_NO_THROW(Validate(w)) << seed;
    const double half = w.floor_size / 2;
    for (double c : w.agent_start) {
      ASSERT_GE(half - std::abs(c), w.agent_radius + kPlacementClearance - 1e-12);
      ASSERT_LE(half - std::abs(c), kCornerInset * w.floor_size + 1e-12);
    }
    ++corners[(w.agent_start[0] > 0) + 2 * (w.agent_start[1] > 0)];
    const BoxParams& b = w.boxes.front();
    const double to_centre = std::atan2(-w.agent_start[1], -w.agent_start[0]);
    const double to_box = std::atan2(b.start[1] - w.agent_start[1], b.start[0] - w.agent_start[0]);
    const double off = std::remainder(to_box - to_centre, 2 * std::numbers::pi);
    ASSERT_LE(std::abs(off), std::numbers::pi / 4 + 1e-9) << seed;
    // every target is farther from the agent than the box is: pushes move
    // the box toward the room, where the targets are
    ASSERT_GT(std::hypot(w.target[0] - w.agent_start[0], w.target[1] - w.agent_start[1]),
              std::hypot(b.start[0] - w.agent_start[0], b.start[1] - w.agent_start[1]));
  }
  for (int n : corners) EXPECT_GT(n, 60);
  // boxes anywhere with the agent in a corner
  d.starts.box_start_gap = -1;
  EXPECT_NO_THROW(GenerateWorld(d, 1));
}

}  // namespace
}  // namespace manyworlds::boxworld
