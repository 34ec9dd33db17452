#include "manyworlds/core/registry.h"

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"
#include "tests/core/toy_env.h"

namespace manyworlds {
namespace {

Registry MakeRegistry() {
  Registry registry;
  registry.Add({"toy", "test", "1-D walker",
                {{"discrete", OptionType::kBool, false, "Discrete(3) actions instead of a Box"},
                 {"limit", OptionType::kInt, 50, "episode limit"},
                 {"scale", OptionType::kFloat, 1.0, "unused scale"},
                 {"mode", OptionType::kString, "a", "mode", {"a", "b"}}},
                [](const Options& o) -> std::unique_ptr<Env> {
                  return std::make_unique<testing::ToyEnv>(o.Bool("discrete"), o.Int("limit"));
                }});
  registry.Add({"toy-long", "test", "same, longer", {},
                [](const Options&) -> std::unique_ptr<Env> {
                  return std::make_unique<testing::ToyEnv>(false, 500);
                }});
  return registry;
}

TEST(RegistryTest, MakesEnvsWithOptions) {
  Registry registry = MakeRegistry();
  auto env = registry.Make("toy", {{"discrete", true}, {"limit", "7"}});
  EXPECT_TRUE(env->spec().action_space.is_discrete());
  EXPECT_EQ(env->spec().max_episode_steps, 7);
  EXPECT_EQ(registry.Make("toy")->spec().max_episode_steps, 50);
  EXPECT_EQ(registry.Make("toy", {{"max_episode_steps", 3}})->spec().max_episode_steps, 3);
  EXPECT_EQ(registry.Ids(), (std::vector<std::string>{"toy", "toy-long"}));
}

TEST(RegistryTest, UnknownIdSuggestsNearest) {
  Registry registry = MakeRegistry();
  try {
    registry.Make("toi");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'toy'"), std::string::npos) << e.what();
  }
}

TEST(RegistryTest, UnknownAndIllTypedOptionsAreErrors) {
  Registry registry = MakeRegistry();
  try {
    registry.Make("toy", {{"limt", 3}});
    FAIL();
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("did you mean 'limit'"), std::string::npos) << what;
  }
  EXPECT_THROW(registry.Make("toy", {{"limit", 2.5}}), ConfigError);
  EXPECT_THROW(registry.Make("toy", {{"limit", "many"}}), ConfigError);
  EXPECT_THROW(registry.Make("toy", {{"discrete", 1}}), ConfigError);
  EXPECT_THROW(registry.Make("toy", {{"mode", "c"}}), ConfigError);
  EXPECT_THROW(registry.Make("toy", {{"max_episode_steps", -4}}), ConfigError);
  // An episode must end: 0 (no limit) and more than 10^6 steps are refused, naming the range.
  for (const int64_t bad : {int64_t{0}, int64_t{1000001}, int64_t{2147483647}}) {
    try {
      registry.Make("toy", {{"max_episode_steps", bad}});
      ADD_FAILURE() << bad;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("[1, 1000000]"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(registry.Make("toy", {{"max_episode_steps", 1000000}})->spec().max_episode_steps,
            1000000);
  EXPECT_THROW(registry.Make("toy", nlohmann::json::array({1})), ConfigError);
  EXPECT_NO_THROW(registry.Make("toy", {{"mode", "b"}, {"scale", "2"}, {"discrete", "true"}}));
}

TEST(RegistryTest, DuplicateIdsAndReservedOptionsAreRejected) {
  Registry registry = MakeRegistry();
  EXPECT_THROW(registry.Add({"toy", "test", "", {}, nullptr}), ConfigError);
  EXPECT_THROW(registry.Add({"new", "test", "", {{"max_episode_steps", OptionType::kInt, 1, ""}},
                             nullptr}),
               ConfigError);
}

TEST(SuggestTest, FindsTyposAndSubstrings) {
  const std::vector<std::string> ids{"cartpole", "acrobot", "point-nav", "point-nav-sparse"};
  EXPECT_NE(SuggestNearest("cartpol", ids).find("cartpole"), std::string::npos);
  EXPECT_NE(SuggestNearest("point", ids).find("point-nav"), std::string::npos);
  EXPECT_EQ(SuggestNearest("zzzzzzzzzz", ids), "");
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3u);
}

}  // namespace
}  // namespace manyworlds
