// The hostile-config probe: every key of every registered algorithm's training config (its
// agent keys and the env, replay, experiment and meta_test sections), given each value of a
// fixed table of hostile override values, on the algorithm's point-nav config
// (configs/point_nav_<algo>.yaml). Stage 1, in this process: `TrainConfig::Load` with the
// override and `Validate` either accept the value or refuse it with a one-line ConfigError.
// Stage 2, each accepted case in a child process (tests/support/child_cases.h; cases whose
// loaded configs are equal, once): the run is
// created and trains one round, then stops as on SIGTERM; it must end with no error or a
// one-line one, within its time and memory, never by a signal.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <new>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "manyworlds/core/error.h"
#include "manyworlds/experiments/algorithms.h"
#include "manyworlds/experiments/train_config.h"
#include "manyworlds/experiments/trainer.h"
#include "tests/experiments/scratch_dirs.h"
#include "tests/support/child_cases.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

// Override values as a user types them after `key=` (parsed as YAML scalars).
const std::vector<std::string>& HostileValues() {
  static const std::vector<std::string> values = {
      ".nan", "nan", ".inf", "-.inf", "1e308", "-1e308", "-1", "0", "9223372036854775807",
      "-9223372036854775808", "18446744073709551616", "", "[[[", "{a: 1}", "[1, 2]", "true",
      "1e9", std::string(5000, 'x')};
  return values;
}

// A run of a few hundred steps (scripts/tiny_runs.py's settings), before the hostile override.
// Algorithms that learn from frames take 40 steps in episodes of 20 and make one update of a
// batch of 8 per task: rendering made them two thirds of the probe's time, and with the
// config's warmup of 500 steps they never reached an update.
std::vector<std::string> TinyOverrides(const AlgorithmInfo& info) {
  const std::string& algo = info.name;
  std::vector<std::string> o = {"experiment.steps_per_task=200", "experiment.eval_every=0",
                                "experiment.eval_episodes=1", "experiment.checkpoint_every=0"};
  if (info.observations == ObservationKind::kPixels) {
    return {"experiment.steps_per_task=40",      "experiment.eval_every=0",
            "experiment.eval_episodes=1",        "experiment.checkpoint_every=0",
            "experiment.warmup_steps=20",        "experiment.updates_per_step=0.05",
            "env.options.max_episode_steps=20",  "agent.batch_size=8"};
  }
  const std::map<std::string, std::vector<std::string>> per_algo = {
      {"sac", {"experiment.warmup_steps=50", "experiment.updates_per_step=0.1"}},
      {"pearl", {"experiment.warmup_steps=0", "agent.updates_per_iteration=5"}},
      {"ppo", {"agent.rollout_rounds=1"}},
      {"trpo", {"agent.rollout_rounds=1"}},
      {"te_ppo", {"agent.rollout_rounds=1"}},
      {"rl2", {"agent.episodes_per_trial=2"}},
      {"maml", {"agent.episodes_per_task=1"}}};
  if (const auto it = per_algo.find(algo); it != per_algo.end()) {
    o.insert(o.end(), it->second.begin(), it->second.end());
  }
  return o;
}

// An algorithm's small config: point_nav_<algo>.yaml, or for algorithms that learn from
// pixels (no point-nav frames) reach_pixels_<algo>.yaml.
fs::path PointNavConfig(const AlgorithmInfo& info) {
  std::string squeezed = info.name;
  std::erase(squeezed, '_');
  const std::string prefix =
      info.observations == ObservationKind::kPixels ? "reach_pixels_" : "point_nav_";
  for (const std::string& name : {info.name, squeezed}) {
    const fs::path file = test_dirs::SourceDir() / "configs" / (prefix + name + ".yaml");
    if (fs::exists(file)) return file;
  }
  return {};
}

// The leaves of a config tree as dotted keys.
void Leaves(const nlohmann::json& tree, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& [key, value] : tree.items()) {
    const std::string path = prefix.empty() ? key : prefix + "." + key;
    if (value.is_object() && !value.empty()) {
      Leaves(value, path, out);
    } else {
      out.push_back(path);
    }
  }
}

struct Case {
  const AlgorithmInfo* info;
  fs::path config;
  std::string key;
  std::string value;
};

std::string Shown(const std::string& value) {
  return value.size() > 20 ? value.substr(0, 8) + "...(" + std::to_string(value.size()) + ")"
                           : value;
}

struct Loaded {
  enum { kAccepted, kRefused, kFailed } verdict;
  std::string detail;  // accepted: the loaded config as JSON; failed: what was wrong
};

// Stage 1: the case's config loaded and validated, or refused with one line.
Loaded LoadCase(const Case& c) {
  std::vector<std::string> overrides = TinyOverrides(*c.info);
  overrides.push_back(c.key + "=" + c.value);
  try {
    const TrainConfig config = TrainConfig::Load(c.config, overrides);
    config.Validate();
    return {Loaded::kAccepted, config.ToJson().dump()};
  } catch (const ConfigError& e) {
    const std::string problem = test_support::ProblemWithMessage(e.what());
    if (problem.empty()) return {Loaded::kRefused, ""};
    return {Loaded::kFailed, problem};
  } catch (const std::exception& e) {
    return {Loaded::kFailed, std::string("not a ConfigError: ") + e.what()};
  }
}

// Stage 2, in the child: "A" trained a round, "E<message>" refused or failed with one line,
// "F<why>". MANYWORLDS_PROBE_VERBOSE=1 prints the E messages.
std::string TrainCase(const Case& c, const fs::path& run_dir) {
  // relative paths (a hostile run_dir of "nan") land in the case's own directory
  fs::create_directories(run_dir.parent_path() / (run_dir.filename().string() + ".cwd"));
  if (chdir((run_dir.parent_path() / (run_dir.filename().string() + ".cwd")).c_str()) != 0) {
    return "Fcannot enter the case's directory";
  }
  std::vector<std::string> overrides = TinyOverrides(*c.info);
  overrides.push_back(c.key + "=" + c.value);
  overrides.push_back("experiment.run_dir=" + run_dir.string());
  if (c.key == "experiment.run_dir") overrides.pop_back();  // the hostile one stays
  try {
    NameMemorySettingsOnFailure([&] {
      const TrainConfig config = TrainConfig::Load(c.config, overrides);
      Trainer trainer = Trainer::Create(config);
      TrainCallbacks callbacks;
      int polls = 0;
      callbacks.stop_requested = [&polls] { return ++polls > 1; };  // one round, as on SIGTERM
      trainer.Run(callbacks);
    });
  } catch (const std::bad_alloc&) {
    return "Fstd::bad_alloc escaped";
  } catch (const std::exception& e) {
    const std::string problem = test_support::ProblemWithMessage(e.what());
    return problem.empty() ? std::string("E") + e.what() : "F" + problem;
  }
  return "A";
}

TEST(ConfigProbeTest, EveryKeyOfEveryAlgorithmTakesHostileValuesWithoutHarm) {
  std::vector<Case> cases;
  std::set<std::string> shared_keys_done;  // env, replay, experiment keys: probed once
  for (const AlgorithmInfo& info : Algorithms()) {
    const fs::path config = PointNavConfig(info);
    ASSERT_FALSE(config.empty()) << "no configs/point_nav_" << info.name
                                 << ".yaml (reach_pixels_ for pixel algorithms): every algorithm "
                                    "has a small config for the probe";
    std::vector<std::string> keys;
    Leaves(TrainConfig::Load(config).ToJson(), "", keys);
    for (const std::string& key : keys) {
      const bool shared = key.rfind("agent.", 0) != 0;
      if (shared && !shared_keys_done.insert(key).second) continue;
      for (const std::string& value : HostileValues()) {
        cases.push_back({&info, config, key, value});
      }
    }
  }
  const auto start = std::chrono::steady_clock::now();
  size_t refused = 0;
  std::vector<size_t> accepted;
  std::string failures;
  size_t failed = 0;
  auto fail = [&](const Case& c, const std::string& why) {
    if (++failed <= 60) {
      failures += "\n  " + c.info->name + " " + c.key + "=" + Shown(c.value) + ": " + why;
    }
  };
  // Accepted cases whose loaded configs are equal (".nan" and "nan"; a value the config already
  // had) train identically: one of them trains, and its verdict stands for all.
  std::map<std::string, size_t> first_with_config;  // config JSON -> index into `distinct`
  std::vector<size_t> distinct;                     // the cases that train
  std::vector<size_t> trained_as;                   // per accepted case: index into `distinct`
  for (size_t i = 0; i < cases.size(); ++i) {
    const Loaded loaded = LoadCase(cases[i]);
    if (loaded.verdict == Loaded::kAccepted) {
      accepted.push_back(i);
      const auto [it, is_new] = first_with_config.try_emplace(loaded.detail, distinct.size());
      if (is_new) distinct.push_back(i);
      trained_as.push_back(it->second);
    } else if (loaded.verdict == Loaded::kRefused) {
      ++refused;
    } else {
      fail(cases[i], loaded.detail);
    }
  }
  const fs::path scratch = test_dirs::Scratch("config_probe", "runs");
  std::vector<double> cpu_seconds;
  const std::vector<std::string> distinct_verdicts = test_support::RunInChildren(
      distinct.size(),
      [&](size_t k) {
        return TrainCase(cases[distinct[k]], scratch / ("case_" + std::to_string(k)));
      },
      {.seconds = 120, .address_space_gib = 8}, &cpu_seconds);
  size_t trained = 0, errors = 0;
  for (size_t k = 0; k < accepted.size(); ++k) {
    const std::string& verdict = distinct_verdicts[trained_as[k]];
    if (verdict == "A") {
      ++trained;
    } else if (verdict[0] == 'E') {
      ++errors;
      if (std::getenv("MANYWORLDS_PROBE_VERBOSE") != nullptr) {
        const Case& c = cases[accepted[k]];
        std::printf("  %s %s=%s: %s\n", c.info->name.c_str(), c.key.c_str(), Shown(c.value).c_str(),
                    verdict.c_str() + 1);
      }
    } else {
      fail(cases[accepted[k]], verdict.substr(1));
    }
  }
  fs::remove_all(scratch);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "config probe: %zu cases (%zu algorithms, %zu hostile values per key) in %.1f s: "
      "%zu refused by the config with one line; %zu accepted (%zu distinct configs "
      "trained), of which %zu trained a round and %zu stopped with a one-line error; %zu "
      "failed\n",
      cases.size(), Algorithms().size(), HostileValues().size(), seconds, refused, accepted.size(),
      distinct.size(), trained, errors, failed);
  // where the probe's time goes: the CI budget is spent here
  std::map<std::string, std::pair<int, double>> per_algorithm;  // trained configs, CPU seconds
  for (size_t k = 0; k < distinct.size(); ++k) {
    auto& [count, cpu] = per_algorithm[cases[distinct[k]].info->name];
    ++count;
    cpu += cpu_seconds[k];
  }
  std::printf("config probe: CPU time of the trained configs per algorithm:");
  for (const auto& [name, count_cpu] : per_algorithm) {
    std::printf(" %s %d in %.1f s;", name.c_str(), count_cpu.first, count_cpu.second);
  }
  std::printf("\n");
  RecordProperty("cases", static_cast<int>(cases.size()));
  EXPECT_EQ(failed, 0u) << failed << " cases failed (the first 60):" << failures;
  EXPECT_GT(cases.size(), 2000u);
  EXPECT_GT(trained, 0u);
}

}  // namespace
}  // namespace manyworlds::experiments
