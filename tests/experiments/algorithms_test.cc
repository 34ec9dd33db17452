// The algorithm registry: every row is whole, names are unique, each config
// reads, prints and validates through its VisitFields, and typed access
// refuses another algorithm's config.
#include "manyworlds/experiments/algorithms.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "manyworlds/agents/ppo/ppo_config.h"
#include "manyworlds/agents/sac/sac_config.h"
#include "manyworlds/agents/te_ppo/te_ppo_config.h"
#include "manyworlds/core/error.h"

namespace manyworlds::experiments {
namespace {

TEST(AlgorithmRegistryTest, EveryRowIsWholeAndNamedOnce) {
  std::set<std::string> names;
  for (const AlgorithmInfo& info : Algorithms()) {
    EXPECT_TRUE(names.insert(info.name).second) << "duplicate row " << info.name;
    EXPECT_FALSE(info.description.empty()) << info.name;
    EXPECT_TRUE(info.discrete_actions || info.box_actions) << info.name;
    ASSERT_NE(info.default_config, nullptr) << info.name;
    EXPECT_NE(info.make, nullptr) << info.name;
    EXPECT_NE(info.bench, nullptr) << info.name;
    EXPECT_EQ(&FindAlgorithm(info.name), &info);
    EXPECT_EQ(LookupAlgorithm(info.name), &info);
  }
  EXPECT_EQ(LookupAlgorithm("sack"), nullptr);
  // the names in errors and help come from the rows, in row order
  std::string joined;
  for (const AlgorithmInfo& info : Algorithms()) joined += (joined.empty() ? "" : ", ") + info.name;
  EXPECT_EQ(AlgorithmNames(), joined);
}

TEST(AlgorithmRegistryTest, UnknownNamesSayWhatIsAllowed) {
  try {
    FindAlgorithm("te-ppo");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'agent.algo': unknown algorithm 'te-ppo'"), std::string::npos) << what;
    EXPECT_NE(what.find("te_ppo"), std::string::npos) << what;  // the nearest name
    EXPECT_NE(what.find("allowed: " + AlgorithmNames()), std::string::npos) << what;
  }
  EXPECT_EQ(UnknownAlgorithm("--algo", "x").rfind("--algo: unknown algorithm 'x'", 0), 0u);
}

TEST(AlgorithmRegistryTest, EveryConfigRoundTripsThroughItsKeys) {
  for (const AlgorithmInfo& info : Algorithms()) {
    const AgentConfig defaults = DefaultAgentConfig(info.name);
    EXPECT_EQ(defaults.algo(), info.name);
    EXPECT_NO_THROW(ValidateAgentConfig(defaults)) << info.name;
    const nlohmann::json json = AgentConfigToJson(defaults);
    EXPECT_EQ(json.at("algo"), info.name);
    EXPECT_GT(json.size(), 3u) << info.name;
    // every printed key is read back: the reader leaves no key unknown
    const AgentConfig again = ReadAgentConfig(json);
    EXPECT_EQ(AgentConfigToJson(again), json) << info.name;
    // and a key of no algorithm is an error naming it
    nlohmann::json bad = json;
    bad["no_such_key"] = 1;
    try {
      ReadAgentConfig(bad);
      ADD_FAILURE() << info.name << ": unknown key accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("no_such_key"), std::string::npos) << e.what();
    }
  }
}

TEST(AlgorithmRegistryTest, ConfigsAreCopiedDeepAndTypedAccessChecksTheAlgorithm) {
  AgentConfig sac = DefaultAgentConfig("sac");
  sac.as<agents::SacConfig>().hidden_dim = 17;
  AgentConfig copy = sac;
  copy.as<agents::SacConfig>().hidden_dim = 23;
  EXPECT_EQ(sac.as<agents::SacConfig>().hidden_dim, 17);
  EXPECT_EQ(copy.as<agents::SacConfig>().hidden_dim, 23);
  EXPECT_THROW(sac.as<agents::PpoConfig>(), ConfigError);
  // TE-PPO's config derives from PPO's, yet it is another algorithm
  const AgentConfig te_ppo = DefaultAgentConfig("te_ppo");
  EXPECT_NO_THROW(te_ppo.as<agents::TePpoConfig>());
  EXPECT_THROW(te_ppo.as<agents::PpoConfig>(), ConfigError);
  // the default agent is the default algorithm's
  EXPECT_EQ(AgentConfig().algo(), "sac");
}

TEST(AlgorithmRegistryTest, OptionalNumbersReadNullAndNumbersOnly) {
  AgentConfig a = ReadAgentConfig({{"algo", "sac"}, {"target_entropy", -1.5}});
  ASSERT_TRUE(a.as<agents::SacConfig>().target_entropy.has_value());
  EXPECT_DOUBLE_EQ(*a.as<agents::SacConfig>().target_entropy, -1.5);
  AgentConfig b = ReadAgentConfig({{"algo", "sac"}, {"target_entropy", nullptr}});
  EXPECT_FALSE(b.as<agents::SacConfig>().target_entropy.has_value());
  EXPECT_TRUE(AgentConfigToJson(b).at("target_entropy").is_null());
  try {
    ReadAgentConfig({{"algo", "sac"}, {"target_entropy", "low"}});
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'agent.target_entropy' must be a number or null"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace manyworlds::experiments

namespace manyworlds::experiments {
namespace {

// Which algorithms act on pixel frames comes from the rows: a state algorithm given obs=pixels
// envs, or a pixel one given the state, is a one-line error naming the algorithms that fit.
TEST(AlgorithmRegistryTest, PixelAndStateAlgorithmsRefuseTheOtherObservations) {
  TaskSet tasks;
  tasks.tasks.push_back({"reach", "reach", {TaskState()}});
  EnvFacts state;
  state.obs_dim = 39;
  state.action_dim = 4;
  state.action_low.assign(4, -1.0f);
  state.action_high.assign(4, 1.0f);
  EnvFacts pixels = state;
  pixels.pixel_shape = {3, 16, 16};
  auto error = [&](const std::string& algo, const EnvFacts& facts) {
    try {
      CheckAlgorithmEnvs(DefaultAgentConfig(algo), facts, tasks);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string ppo = error("ppo", pixels);
  EXPECT_NE(ppo.find("agent.algo 'ppo' learns from the state, but env 'reach' has obs=pixels"),
            std::string::npos)
      << ppo;
  EXPECT_NE(ppo.find("sac, sac_ae"), std::string::npos) << ppo;
  const std::string ae = error("sac_ae", state);
  EXPECT_NE(ae.find("learns from pixel frames"), std::string::npos) << ae;
  EXPECT_NE(ae.find("set env.options.obs=pixels"), std::string::npos) << ae;
  EXPECT_EQ(error("sac", state), "");
  EXPECT_EQ(error("sac", pixels), "");
  EXPECT_EQ(error("sac_ae", pixels), "");
}

}  // namespace
}  // namespace manyworlds::experiments
