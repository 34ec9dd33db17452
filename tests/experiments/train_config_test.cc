#include "manyworlds/experiments/train_config.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <set>
#include <string>

#include "manyworlds/agents/sac/sac_config.h"
#include "manyworlds/core/error.h"
#include "manyworlds/envs/all.h"
#include "manyworlds/experiments/evaluation/evaluator.h"
#include "manyworlds/experiments/evaluation/meta_test_protocol.h"
#include "manyworlds/experiments/loops/collector.h"
#include "manyworlds/experiments/run/run_log.h"
#include "manyworlds/experiments/task_set.h"
#include "tests/experiments/scratch_dirs.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

using test_dirs::SourceDir;

// Created, unlike test_dirs::Scratch's.
fs::path Scratch(const std::string& name) {
  fs::path dir = test_dirs::Scratch("train_config", name);
  fs::create_directories(dir);
  return dir;
}

fs::path WriteFile(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(TrainConfigTest, DefaultsFollowMtrl) {
  TrainConfig c;
  EXPECT_EQ(c.agent.as<agents::SacConfig>().hidden_dim, 400);
  EXPECT_EQ(c.agent.as<agents::SacConfig>().num_layers, 3);
  EXPECT_EQ(c.experiment.warmup_steps, 1500);
  EXPECT_EQ(c.replay.capacity, 1000000);
  EXPECT_EQ(c.replay.sampling, "balanced");
  EXPECT_EQ(c.TotalBatchSize(10), 1280);  // 128 per task
  c.experiment.batch_size = 256;
  EXPECT_EQ(c.TotalBatchSize(10), 256);
  // no env given
  EXPECT_NE(ErrorOf([&] { TrainConfig{}.Validate(); }).find("env.id"), std::string::npos);
}

TEST(TrainConfigTest, LoadsYamlThenOverridesAndRoundTrips) {
  const fs::path dir = Scratch("load");
  const fs::path file = WriteFile(dir / "c.yaml", R"(
env:
  id: point-nav
  options: {horizon: 50}
agent:
  hidden_dim: 32
  target_entropy: -1.5
  architecture: multihead
experiment:
  steps_per_task: 1000
)");
  TrainConfig c = TrainConfig::Load(file, {"experiment.seed=7", "agent.num_layers=1",
                                           "env.options.horizon=20"});
  EXPECT_EQ(c.env.id, "point-nav");
  EXPECT_EQ(c.env.options["horizon"], 20);
  EXPECT_EQ(c.agent.as<agents::SacConfig>().hidden_dim, 32);
  EXPECT_EQ(c.agent.as<agents::SacConfig>().num_layers, 1);
  EXPECT_EQ(c.agent.as<agents::SacConfig>().architecture, "multihead");
  ASSERT_TRUE(c.agent.as<agents::SacConfig>().target_entropy.has_value());
  EXPECT_DOUBLE_EQ(*c.agent.as<agents::SacConfig>().target_entropy, -1.5);
  EXPECT_EQ(c.experiment.seed, 7u);
  EXPECT_EQ(c.experiment.steps_per_task, 1000);
  EXPECT_EQ(c.experiment.warmup_steps, 1500);  // default kept
  EXPECT_NO_THROW(c.Validate());
  // the resolved tree reads back to the same config
  EXPECT_EQ(TrainConfig::FromJson(c.ToJson()).ToJson(), c.ToJson());
}

TEST(TrainConfigTest, UnknownKeysAndBadValuesAreConfigErrors) {
  const fs::path dir = Scratch("bad");
  const fs::path typo = WriteFile(dir / "typo.yaml", "env: {id: point-nav}\nagent: {hiden_dim: 3}\n");
  std::string e = ErrorOf([&] { TrainConfig::Load(typo); });
  EXPECT_NE(e.find("agent.hiden_dim"), std::string::npos) << e;
  EXPECT_NE(e.find("hidden_dim"), std::string::npos) << e;  // suggestion
  EXPECT_NE(e.find("typo.yaml"), std::string::npos) << e;
  const fs::path section = WriteFile(dir / "section.yaml", "envs: {id: point-nav}\n");
  EXPECT_NE(ErrorOf([&] { TrainConfig::Load(section); }), "");
  const fs::path type = WriteFile(dir / "type.yaml", "experiment: {steps_per_task: lots}\n");
  EXPECT_NE(ErrorOf([&] { TrainConfig::Load(type); }).find("experiment.steps_per_task"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { TrainConfig::Load(std::nullopt, {"experiment.sede=1"}); }), "");

  auto invalid = [](const std::function<void(TrainConfig&)>& mutate) {
    TrainConfig c;
    c.env.id = "point-nav";
    mutate(c);
    return ErrorOf([&] { c.Validate(); });
  };
  EXPECT_EQ(invalid([](TrainConfig&) {}), "");
  EXPECT_NE(invalid([](TrainConfig& c) { c.env.tasks = {"reach"}; }).find("exclusive"),
            std::string::npos);
  EXPECT_NE(invalid([](TrainConfig& c) { c.env.envs_per_task = 0; }).find("envs_per_task"),
            std::string::npos);
  EXPECT_NE(invalid([](TrainConfig& c) { c.replay.sampling = "weighted"; }).find("sampling"),
            std::string::npos);
  EXPECT_NE(invalid([](TrainConfig& c) { c.experiment.updates_per_step = -1; })
                .find("updates_per_step"),
            std::string::npos);
  EXPECT_NE(invalid([](TrainConfig& c) { c.experiment.eval_episodes = 0; }).find("eval_episodes"),
            std::string::npos);
  EXPECT_NE(invalid([](TrainConfig& c) { c.experiment.num_threads = 0; }).find("num_threads"),
            std::string::npos);
  EXPECT_NE(invalid([](TrainConfig& c) { c.agent.as<agents::SacConfig>().discount = 2; }), "");
  EXPECT_NE(
      invalid([](TrainConfig& c) { c.agent.as<agents::SacConfig>().architecture = "transformer"; }),
      "");
  EXPECT_NE(invalid([](TrainConfig& c) { c.env.task_states = {{{"goal", 1}}}; })
                .find("task_states"),
            std::string::npos);
}

TEST(TrainConfigTest, ShippedConfigsLoadAndValidate) {
  int count = 0;
  // configs with one env section (14 share MT10's) build their envs once: the envs depend on
  // that section alone, and building MT10's and MT50's Meta-World tasks is most of this test
  std::set<std::string> env_sections_checked;
  for (const auto& entry : fs::directory_iterator(SourceDir() / "configs")) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".yaml" || name == "demo.yaml") continue;
    SCOPED_TRACE(name);
    TrainConfig c;
    ASSERT_NO_THROW(c = TrainConfig::Load(entry.path()));
    EXPECT_NO_THROW(c.Validate());
    EXPECT_EQ(c.experiment.run_dir, "runs/" + entry.path().stem().string());
    // the envs exist and the tasks resolve (MT10 builds ten MuJoCo tasks)
    const bool new_env_section = env_sections_checked.insert(c.ToJson()["env"].dump()).second;
    if ((new_env_section || name == "point_nav3_mtsac.yaml") &&
        DefaultRegistry().Contains(c.env.id.empty() ? c.env.tasks.front() : c.env.id)) {
      const TaskSet tasks = ResolveTasks(c.env, DefaultRegistry());
      EXPECT_GE(tasks.size(), 1);
      if (c.env.id == "mt10") {
        EXPECT_EQ(tasks.size(), 10);
      }
      if (name == "point_nav3_mtsac.yaml") {
        EXPECT_EQ(tasks.size(), 3);
      }
      const EnvFacts facts = InspectEnvs(tasks, DefaultRegistry());
      EXPECT_GT(facts.episode_length, 0);
    }
    ++count;
  }
  EXPECT_GE(count, 8);
}

TEST(TaskSetTest, ResolvesListsSamplesAndExplicitStates) {
  const Registry& registry = DefaultRegistry();
  EnvSectionConfig env;
  env.id = "point-nav";
  env.num_tasks = 3;
  TaskSet sampled = ResolveTasks(env, registry);
  ASSERT_EQ(sampled.size(), 3);
  EXPECT_EQ(sampled.tasks[1].name, "point-nav/1");
  EXPECT_NE(sampled.tasks[0].variations[0], sampled.tasks[1].variations[0]);
  // deterministic in task_seed, and it round-trips through JSON
  EXPECT_EQ(ResolveTasks(env, registry).ToJson(), sampled.ToJson());
  EXPECT_EQ(TaskSet::FromJson(sampled.ToJson()).ToJson(), sampled.ToJson());
  env.task_seed = 5;
  EXPECT_NE(ResolveTasks(env, registry).ToJson(), sampled.ToJson());

  EnvSectionConfig list;
  list.tasks = {"point-nav", "point-nav", "cartpole"};
  TaskSet named = ResolveTasks(list, registry);
  EXPECT_EQ(named.tasks[0].name, "point-nav");
  EXPECT_EQ(named.tasks[1].name, "point-nav#1");
  EXPECT_EQ(named.tasks[2].env_id, "cartpole");

  EnvSectionConfig explicit_states;
  explicit_states.id = "point-nav";
  explicit_states.task_states = nlohmann::json::parse(
      R"([{"env": "point-nav", "params": {"goal": [0.1, 0.2]}}])");
  EXPECT_EQ(ResolveTasks(explicit_states, registry).tasks[0].variations[0].params["goal"][1],
            0.2);
  explicit_states.task_states[0]["params"]["goal"] = {9.0, 0.0};  // outside the range
  EXPECT_NE(ErrorOf([&] { ResolveTasks(explicit_states, registry); }).find("task_states.0"),
            std::string::npos);
  EnvSectionConfig unknown;
  unknown.id = "point-nva";
  EXPECT_NE(ErrorOf([&] { ResolveTasks(unknown, registry); }).find("point-nav"),
            std::string::npos);
  // cartpole (discrete actions, other sizes) cannot join a SAC run
  EXPECT_NE(ErrorOf([&] { InspectEnvs(named, registry); }).find("cartpole"), std::string::npos);
}

// A default registration to add to another registry: without the options
// every registry adds itself.
EnvRegistration Registration(const std::string& id) {
  EnvRegistration r = DefaultRegistry().Find(id);
  std::erase_if(r.options, [](const OptionSpec& o) {
    const auto& reserved = Registry::ReservedOptions();
    return std::find(reserved.begin(), reserved.end(), o.name) != reserved.end();
  });
  return r;
}

// Every env a collector or protocol steps is built once, and the task set's
// facts come from those envs, not from envs built only to be looked at.
TEST(TaskSetTest, CollectorsAndProtocolsBuildEachEnvOnceAndReadItsFacts) {
  Registry registry;
  EnvRegistration point_nav = Registration("point-nav");
  int built = 0;
  const EnvFactory make = point_nav.factory;
  point_nav.factory = [&built, make](const Options& options) {
    ++built;
    return make(options);
  };
  registry.Add(point_nav);
  EnvSectionConfig env;
  env.id = "point-nav";
  env.num_tasks = 3;
  const TaskSet tasks = ResolveTasks(env, registry);
  built = 0;
  const Collector collector(tasks, registry, /*envs_per_task=*/2, /*num_threads=*/1);
  EXPECT_EQ(built, 6);
  const EnvFacts inspected = InspectEnvs(tasks, registry);
  EXPECT_EQ(collector.facts().obs_dim, inspected.obs_dim);
  EXPECT_EQ(collector.facts().action_high, inspected.action_high);
  EXPECT_EQ(collector.facts().episode_length, inspected.episode_length);
  built = 0;
  const Evaluator evaluator(tasks, registry, /*episodes_per_task=*/4, /*seed=*/1, 1);
  EXPECT_EQ(built, 12);  // one env per episode slot
  EXPECT_EQ(evaluator.facts().success_index, inspected.success_index);
  built = 0;
  MetaTestConfig meta;
  meta.protocol = kPerVariation;
  meta.trials_per_task = 2;
  const MetaTestProtocol protocol(tasks, registry, meta, /*seed=*/1, 1);
  EXPECT_EQ(built, 6);
  built = 0;
  MetaTestConfig v3;
  v3.meta_batch_size = 3;
  const MetaTestProtocol metalearning(tasks, registry, v3, /*seed=*/1, 1);
  EXPECT_EQ(built, 3);  // meta_batch_size envs in all
  // the facts' checks still hold: cartpole cannot join point-nav's tasks
  registry.Add(Registration("cartpole"));
  EnvSectionConfig mixed;
  mixed.tasks = {"point-nav", "cartpole"};
  const TaskSet mixed_tasks = ResolveTasks(mixed, registry);
  EXPECT_NE(ErrorOf([&] { Collector(mixed_tasks, registry, 1, 1); }).find("cartpole"),
            std::string::npos);
}

TEST(RunLogTest, JsonLinesWithCsvThatGrowsColumnsAndTruncates) {
  const fs::path dir = Scratch("log");
  {
    RunLog log(dir, "m");
    log.Append({{"step", 1}, {"a", 1.5}});
    log.Append({{"step", 2}, {"a", 2.5}, {"b", nullptr}});
    log.Append({{"step", 3}, {"a", 3.5}, {"nested", {{"x", 1}, {"y", "s,t"}}}});
  }
  auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  EXPECT_EQ(slurp(dir / "m.csv"),
            "step,a,b,nested.x,nested.y\n1,1.5,,,\n2,2.5,,,\n3,3.5,,1,\"s,t\"\n");
  EXPECT_EQ(ReadJsonLines(dir / "m.jsonl").size(), 3u);
  RunLog reopened(dir, "m");
  reopened.TruncateAfter(2);
  EXPECT_EQ(ReadJsonLines(dir / "m.jsonl").size(), 2u);
  EXPECT_EQ(slurp(dir / "m.csv"), "step,a,b\n1,1.5,\n2,2.5,\n");
  reopened.Append({{"step", 3}, {"a", 4.0}});
  EXPECT_EQ(slurp(dir / "m.csv"), "step,a,b\n1,1.5,\n2,2.5,\n3,4.0,\n");
  // a line torn by a crash at the end is skipped
  std::ofstream(dir / "m.jsonl", std::ios::app) << "{\"step\": 4, \"a\"";
  EXPECT_EQ(ReadJsonLines(dir / "m.jsonl").size(), 3u);
}

}  // namespace
}  // namespace manyworlds::experiments
