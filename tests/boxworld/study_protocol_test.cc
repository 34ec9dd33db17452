// The study's task protocol on the box world (docs/boxworld.md "The study"):
// targets_per_layout groups consecutive task draws on one layout, and
// target_in_obs puts the target into the env observation.
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "manyworlds/boxworld/boxworld.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"

namespace manyworlds::boxworld {
namespace {

Registry MakeRegistry() {
  Registry registry;
  RegisterBoxWorldSuite(registry);
  return registry;
}

std::vector<WorldParams> Draw(const std::string& id, const nlohmann::json& options,
                              uint64_t task_seed, int n) {
  const Registry registry = MakeRegistry();
  auto env = registry.Make(id, options);
  env->SeedTask(task_seed);
  std::vector<WorldParams> worlds;
  for (int i = 0; i < n; ++i) worlds.push_back(WorldFromJson(env->SampleTaskState().params));
  return worlds;
}

// Everything but the target: floor, boxes (with their starts), agent start.
bool SameLayout(WorldParams a, WorldParams b) {
  a.target = b.target;
  return a == b;
}

TEST(StudyProtocolTest, ConsecutiveDrawsShareALayoutPerGroup) {
  const int group = 3;
  const auto worlds = Draw("box-world-simple", {{"targets_per_layout", group}}, 7, 4 * group);
  for (int g = 0; g < 4; ++g) {
    std::set<std::pair<double, double>> targets;
    for (int i = 0; i < group; ++i) {
      const WorldParams& w = worlds[g * group + i];
      EXPECT_TRUE(SameLayout(w, worlds[g * group])) << "group " << g << " draw " << i;
      targets.insert({w.target[0], w.target[1]});
    }
    EXPECT_EQ(targets.size(), static_cast<size_t>(group)) << "targets repeat in group " << g;
    if (g > 0) {
      EXPECT_FALSE(SameLayout(worlds[g * group], worlds[(g - 1) * group])) << "group " << g;
      EXPECT_NE(worlds[g * group].agent_start, worlds[(g - 1) * group].agent_start);
    }
  }
}

TEST(StudyProtocolTest, BroadGroupsShareFloorAndBoxesToo) {
  const nlohmann::json options = {{"targets_per_layout", 4}, {"floor_size", 4.0},
                                  {"floor_size_max", 8.0},   {"num_boxes", 1},
                                  {"num_boxes_max", 3},      {"box_shapes", "box,sphere"}};
  const auto worlds = Draw("box-world-complex", options, 3, 12);
  std::set<double> floors;
  for (int i = 0; i < 12; ++i) {
    EXPECT_TRUE(SameLayout(worlds[i], worlds[i / 4 * 4])) << i;
    floors.insert(worlds[i].floor_size);
  }
  EXPECT_EQ(floors.size(), 3u);  // a floor per group
}

TEST(StudyProtocolTest, SeedTaskRestartsTheGroupsAndTestLayoutsAreNotTrainingOnes) {
  // the same seed gives the same sequence, group boundaries included
  const auto a = Draw("box-world-simple", {{"targets_per_layout", 9}}, 0, 27);
  const auto b = Draw("box-world-simple", {{"targets_per_layout", 9}}, 0, 27);
  EXPECT_EQ(a, b);
  // the study's training worlds (seed 0, 20 layouts x 9) and test worlds
  // (seed 1000, 4 layouts x 9: 5 support + 4 query targets) share no layout
  const auto train = Draw("box-world-simple", {{"targets_per_layout", 9}}, 0, 180);
  const auto test = Draw("box-world-simple", {{"targets_per_layout", 9}}, 1000, 36);
  std::set<std::pair<double, double>> train_starts;
  for (const auto& w : train) train_starts.insert({w.agent_start[0], w.agent_start[1]});
  EXPECT_EQ(train_starts.size(), 20u);
  for (const auto& w : test) {
    EXPECT_EQ(train_starts.count({w.agent_start[0], w.agent_start[1]}), 0u);
    for (const auto& t : train) EXPECT_FALSE(SameLayout(w, t));
  }
}

TEST(StudyProtocolTest, BadGroupOptionsAreOneLineErrors) {
  const Registry registry = MakeRegistry();
  try {
    registry.Make("box-world-simple", {{"targets_per_layout", 0}});
    FAIL() << "targets_per_layout 0 accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'targets_per_layout' must be >= 1, got 0"),
              std::string::npos) << e.what();
  }
  try {
    registry.Make("box-world-simple", {{"targets_per_layout", 4}, {"layout_seed", 2}});
    FAIL() << "targets_per_layout with a fixed layout accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("needs layout_seed = -1"), std::string::npos)
        << e.what();
  }
}

TEST(StudyProtocolTest, TargetInObsAppendsTheTargetOrZerosWhenHidden) {
  const Registry registry = MakeRegistry();
  auto plain = registry.Make("box-world-simple", {});
  auto shown = registry.Make("box-world-simple", {{"target_in_obs", true}});
  auto hidden = registry.Make("box-world-simple", {{"target_in_obs", true}, {"hide_target", true}});
  const int64_t base = plain->spec().env_obs_space.flat_size();
  ASSERT_EQ(shown->spec().env_obs_space.flat_size(), base + 2);
  ASSERT_EQ(hidden->spec().env_obs_space.flat_size(), base + 2);
  for (auto* env : {shown.get(), hidden.get()}) {
    env->SeedTask(5);
    env->ResetTaskState();
  }
  const WorldParams w = WorldFromJson(shown->GetTaskState().params);
  const Observation o = shown->Reset();
  EXPECT_FLOAT_EQ(o.env_obs[base], static_cast<float>(w.target[0]));
  EXPECT_FLOAT_EQ(o.env_obs[base + 1], static_cast<float>(w.target[1]));
  EXPECT_NE(o.env_obs[base], 0.0f);
  const Observation h = hidden->Reset();
  EXPECT_EQ(h.env_obs[base], 0.0f);
  EXPECT_EQ(h.env_obs[base + 1], 0.0f);
}

}  // namespace
}  // namespace manyworlds::boxworld
