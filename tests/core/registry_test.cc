#include "manyworlds/core/registry.h"

#include <gtest/gtest.h>

#include <cmath>

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

// What a hostile value gives: the ConfigError's message (empty: no error).
std::string MakeError(const Registry& registry, const nlohmann::json& options) {
  try {
    registry.Make("toy", options);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
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
  // the env's own limit too: an episode of 10^15 steps is refused, not run (it hung)
  EXPECT_NE(MakeError(registry, {{"limit", int64_t{1000000000000000}}})
                .find("episodes of 1000000000000000 steps, more than the 1000000 allowed"),
            std::string::npos);
  EXPECT_EQ(registry.Make("toy", {{"limit", 1000000000000000}, {"max_episode_steps", 10}})
                ->spec().max_episode_steps,
            10);
  EXPECT_THROW(registry.Make("toy", nlohmann::json::array({1})), ConfigError);
  EXPECT_NO_THROW(registry.Make("toy", {{"mode", "b"}, {"scale", "2"}, {"discrete", "true"}}));
}

TEST(RegistryTest, HostileOptionValuesAreShortOneLineErrors) {
  Registry registry = MakeRegistry();
  // 60,000 nested lists, as a string and as a value: refused without printing them (printing
  // one in full overflowed the stack: SIGSEGV)
  nlohmann::json as_string = nlohmann::json::object();
  as_string["limit"] = std::string(60000, '[') + std::string(60000, ']');
  nlohmann::json as_value = nlohmann::json::object();
  nlohmann::json nested = nlohmann::json::array();
  for (int i = 0; i < 60000; ++i) {
    nlohmann::json outer = nlohmann::json::array();
    outer.push_back(std::move(nested));
    nested = std::move(outer);
  }
  as_value["limit"] = std::move(nested);  // moved, never copied: a copy recurses
  for (const nlohmann::json* options : {&as_string, &as_value}) {
    const std::string what = MakeError(registry, *options);
    EXPECT_NE(what.find("option 'limit' has value"), std::string::npos) << what.substr(0, 300);
    EXPECT_LT(what.size(), 300u);
  }
  EXPECT_NE(MakeError(registry, {{"limit", "[1, 2]"}}).find("has value '[1, 2]'"),
            std::string::npos);
  EXPECT_NE(MakeError(registry, {{"limit", nlohmann::json::array({1, 2})}})
                .find("has value a list of 2 items"),
            std::string::npos);
  // integers in [2^63, 2^64) are unsigned in JSON: refused, not wrapped to negative numbers
  for (const nlohmann::json& value :
       {nlohmann::json(uint64_t{18446744073709551615u}), nlohmann::json("18446744073709551615"),
        nlohmann::json("9223372036854775809"), nlohmann::json(uint64_t{9223372036854775808u})}) {
    const std::string what = MakeError(registry, {{"limit", value}});
    EXPECT_NE(what.find("beyond the integers [-2^63, 2^63)"), std::string::npos)
        << value << ": " << what;
  }
  // the largest int64 is an integer (then out of the env's own range)
  EXPECT_EQ(MakeError(registry, {{"scale", "9223372036854775807"}}), "");
  // a string value longer than 4096 characters is refused by its length, not echoed (the box
  // world echoed 100,000 characters); a shorter one is cut in the message
  std::string what = MakeError(registry, {{"mode", std::string(100000, 'x')}});
  EXPECT_NE(what.find("has a value of 100000 characters, more than 4096"), std::string::npos)
      << what;
  what = MakeError(registry, {{"mode", std::string(4000, 'x')}});
  EXPECT_NE(what.find("has value 'xxx"), std::string::npos) << what;
  EXPECT_LT(what.size(), 400u);
}

TEST(RegistryTest, RangesAndLongChoiceListsGiveShortMessages) {
  Registry registry;
  std::vector<std::string> names;
  for (int i = 0; i < 50; ++i) names.push_back("task-number-" + std::to_string(i));
  OptionSpec ranged{"gain", OptionType::kFloat, 1.0, "a gain", {}, -10.0, 10.0};
  registry.Add({"many", "test", "", {{"task", OptionType::kString, names[0], "a task", names},
                                     ranged},
                [](const Options&) -> std::unique_ptr<Env> {
                  return std::make_unique<testing::ToyEnv>(false, 5);
                }});
  auto error = [&](const nlohmann::json& options) {
    try {
      registry.Make("many", options);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // 50 names are summarised with the nearest one (mt1's task list made 760 characters)
  const std::string task = error({{"task", "task-number-7x"}});
  EXPECT_NE(task.find("did you mean 'task-number-7'"), std::string::npos) << task;
  EXPECT_NE(task.find("one of 50 names (task-number-0"), std::string::npos) << task;
  EXPECT_LT(task.size(), 400u) << task;
  // a declared range is checked before the env is made
  EXPECT_NE(error({{"gain", 11.0}}).find("outside [-10, 10]"), std::string::npos);
  EXPECT_NE(error({{"gain", "-1e308"}}).find("outside [-10, 10]"), std::string::npos);
  EXPECT_EQ(error({{"gain", 10.0}}), "");
  // non-finite numbers are named as such (JSON would print them as null)
  EXPECT_NE(error({{"gain", std::nan("")}}).find("has value nan"), std::string::npos)
      << error({{"gain", std::nan("")}});
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
