#include "manyworlds/config/reader.h"

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

struct RolloutConfig {
  int episodes = 10;
  uint64_t seed = 0;
  double gamma = 0.99;
  float scale = 1.0f;
  bool render = false;
  std::string policy = "random";
  std::vector<std::string> envs;
};

RolloutConfig Bind(const nlohmann::json& j) {
  RolloutConfig cfg;
  ConfigReader r(j, "rollout");
  r.Read("episodes", cfg.episodes);
  r.Read("seed", cfg.seed);
  r.Read("gamma", cfg.gamma);
  r.Read("scale", cfg.scale);
  r.Read("render", cfg.render);
  r.Read("policy", cfg.policy);
  r.Read("envs", cfg.envs);
  r.Finish();
  return cfg;
}

std::string ErrorOf(const std::string& json) {
  try {
    Bind(nlohmann::json::parse(json));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigReaderTest, AbsentKeysKeepDefaults) {
  const RolloutConfig cfg = Bind(nlohmann::json::parse(R"({"episodes": 3, "gamma": 1})"));
  EXPECT_EQ(cfg.episodes, 3);
  EXPECT_DOUBLE_EQ(cfg.gamma, 1.0);
  EXPECT_EQ(cfg.policy, "random");
  EXPECT_EQ(Bind(nullptr).episodes, 10);
}

TEST(ConfigReaderTest, UnknownKeysSuggestTheNearest) {
  EXPECT_EQ(ErrorOf(R"({"episdoes": 3})"),
            "unknown key 'rollout.episdoes' (did you mean 'episodes'?)");
  EXPECT_EQ(ErrorOf(R"({"zzzzzzzz": 3})"), "unknown key 'rollout.zzzzzzzz'");
}

TEST(ConfigReaderTest, TypeErrorsNameKeyAndType) {
  EXPECT_EQ(ErrorOf(R"({"episodes": "ten"})"),
            "config key 'rollout.episodes' must be an int, got \"ten\" (string)");
  EXPECT_NE(ErrorOf(R"({"episodes": 2.5})").find("must be an int"), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"episodes": 1e12})").find("must be an int"), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"episodes": 99999999999})").find("must be an int"), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"seed": -1})").find("must be a non-negative int"), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"render": 1})").find("must be a bool"), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"envs": ["a", 1]})").find("'rollout.envs' must be a list of strings"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"gamma": "x"})").find("must be a number"), std::string::npos);
}

TEST(ConfigReaderTest, SectionsNestPaths) {
  const auto j = nlohmann::json::parse(R"({"agent": {"lr": 0.1, "lrr": 2}})");
  ConfigReader root(j);
  ConfigReader agent = root.Section("agent");
  double lr = 0;
  agent.Read("lr", lr);
  root.Finish();
  try {
    agent.Finish();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "unknown key 'agent.lrr' (did you mean 'lr'?)");
  }
  ConfigReader missing = root.Section("absent");
  missing.Finish();
  EXPECT_THROW(ConfigReader(nlohmann::json(3), "x"), ConfigError);
}

}  // namespace
}  // namespace manyworlds
