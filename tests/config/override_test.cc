#include "manyworlds/config/override.h"

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

nlohmann::json Base() {
  return nlohmann::json::parse(
      R"({"seed": 0, "rollout": {"episodes": 10, "policy": "random"}, "envs": ["a", "b"]})");
}

std::string ErrorOf(nlohmann::json& config, const std::string& text) {
  try {
    ApplyOverride(config, text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(OverrideTest, ValuesAreParsedAsYaml) {
  auto c = Base();
  ApplyOverride(c, "seed=3");
  ApplyOverride(c, "rollout.episodes=0.5");
  ApplyOverride(c, "rollout.policy=scripted");
  ApplyOverride(c, "envs=[1,2]");
  EXPECT_EQ(c["seed"], 3);
  EXPECT_TRUE(c["rollout"]["episodes"].is_number_float());
  EXPECT_EQ(c["rollout"]["policy"], "scripted");
  EXPECT_EQ(c["envs"], nlohmann::json::parse("[1, 2]"));
  ApplyOverride(c, "seed=true");
  EXPECT_EQ(c["seed"], true);
  ApplyOverride(c, "seed=");
  EXPECT_EQ(c["seed"], "");
  ApplyOverride(c, "seed=a=b");
  EXPECT_EQ(c["seed"], "a=b");
}

TEST(OverrideTest, ListItemsByIndex) {
  auto c = Base();
  ApplyOverride(c, "envs.1=c");
  EXPECT_EQ(c["envs"], nlohmann::json::parse(R"(["a", "c"])"));
  EXPECT_NE(ErrorOf(c, "envs.2=c").find("not a valid index"), std::string::npos);
}

TEST(OverrideTest, UnknownKeySuggestsTheNearest) {
  auto c = Base();
  const std::string e = ErrorOf(c, "rollout.episdoes=5");
  EXPECT_NE(e.find("'rollout' has no key 'episdoes' (did you mean 'episodes'?)"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("+rollout.episdoes="), std::string::npos) << e;
  EXPECT_NE(ErrorOf(c, "sed=1").find("did you mean 'seed'"), std::string::npos);
  EXPECT_EQ(c, Base());
}

TEST(OverrideTest, PlusAddsNewKeysAndSections) {
  auto c = Base();
  ApplyOverride(c, "+rollout.note=hi");
  ApplyOverride(c, "+extra.deep.x=1");
  EXPECT_EQ(c["rollout"]["note"], "hi");
  EXPECT_EQ(c["extra"]["deep"]["x"], 1);
  EXPECT_NE(ErrorOf(c, "+seed=1").find("already exists"), std::string::npos);
  ApplyOverride(c, "++seed=9");
  ApplyOverride(c, "++fresh=2");
  EXPECT_EQ(c["seed"], 9);
  EXPECT_EQ(c["fresh"], 2);
}

TEST(OverrideTest, MalformedOverridesAreErrors) {
  auto c = Base();
  EXPECT_NE(ErrorOf(c, "seed").find("not of the form key=value"), std::string::npos);
  EXPECT_NE(ErrorOf(c, "=3").find("empty key"), std::string::npos);
  EXPECT_NE(ErrorOf(c, "rollout..episodes=3").find("empty part"), std::string::npos);
  EXPECT_NE(ErrorOf(c, "seed.x=3").find("is a value, not a section"), std::string::npos);
  EXPECT_NE(ErrorOf(c, "seed=[1,").find("override 'seed=[1,'"), std::string::npos);
}

}  // namespace
}  // namespace manyworlds
