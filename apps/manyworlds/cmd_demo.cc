// manyworlds demo [CONFIG] [key=value ...] [--out DIR]: a seeded rollout of
// every configured env, a summary table, and config.yaml / results.json /
// results.csv written atomically into the output directory.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "apps/manyworlds/demo_config.h"
#include "manyworlds/core/atomic_file.h"
#include "manyworlds/config/yaml.h"
#include "manyworlds/core/error.h"
#include "manyworlds/envs/all.h"

namespace manyworlds::cli {
namespace {

namespace fs = std::filesystem;

constexpr char kDefaultConfig[] = "configs/demo.yaml";

struct DemoArgs {
  std::vector<std::string> positional;  // [CONFIG] then overrides
  std::string out;
};

struct EnvResult {
  std::string env;
  RolloutSummary summary;
  double steps_per_s = 0.0;
};

EnvResult RunOne(const std::string& id, const DemoConfig& config) {
  auto env = Make(id);
  const auto start = std::chrono::steady_clock::now();
  EnvResult result{id, SeededRollout(*env, config.policy, config.seed, config.task_seed,
                                     config.episodes)};
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  int64_t steps = 0;
  for (const auto& e : result.summary.episodes) steps += e.length;
  result.steps_per_s = seconds > 0 ? static_cast<double>(steps) / seconds : 0.0;
  return result;
}

nlohmann::json NullIfNegative(double rate) {
  return rate < 0 ? nlohmann::json() : nlohmann::json(rate);
}

std::string ResultsCsv(const std::vector<EnvResult>& results, int episodes) {
  std::ostringstream csv;
  csv << "env,episodes,mean_return,mean_length,success_rate,steps_per_s\n";
  for (const auto& r : results) {
    csv << r.env << "," << episodes << "," << nlohmann::json(r.summary.mean_return).dump() << ","
        << nlohmann::json(r.summary.mean_length).dump() << ","
        << (r.summary.success_rate < 0 ? "" : nlohmann::json(r.summary.success_rate).dump())
        << "," << Fixed(r.steps_per_s, 0) << "\n";
  }
  return csv.str();
}

void RunDemo(const DemoArgs& args, const CommandContext& context) {
  // the first argument without '=' is the config file; the rest are overrides
  std::optional<fs::path> file;
  std::vector<std::string> overrides;
  for (const auto& arg : args.positional) {
    if (arg.find('=') != std::string::npos) {
      overrides.push_back(arg);
    } else if (!file && overrides.empty()) {
      file = arg;
    } else {
      throw ConfigError("'" + arg + "' is not an override of the form key=value");
    }
  }
  if (!file && fs::exists(kDefaultConfig)) file = kDefaultConfig;
  DemoConfig config = DemoConfig::Load(file, overrides);
  if (!args.out.empty()) config.out_dir = args.out;
  config.Resolve(DefaultRegistry());
  if (!file) std::cerr << "demo: no " << kDefaultConfig << " here; using built-in defaults\n";

  std::vector<EnvResult> results;
  {
    ProgressBar progress("demo", static_cast<int64_t>(config.envs.size()), "envs",
                         context.progress);
    for (const auto& id : config.envs) {
      results.push_back(RunOne(id, config));
      progress.Advance();
    }
  }

  Table table({"env", ">mean return", ">mean length", ">success rate", ">env steps/s"});
  nlohmann::json json_results = nlohmann::json::array();
  for (const auto& r : results) {
    table.AddRow({r.env, Fixed(r.summary.mean_return, 3), Fixed(r.summary.mean_length, 1),
                  SuccessRate(r.summary.success_rate), Human(r.steps_per_s)});
    json_results.push_back({{"env", r.env},
                            {"mean_return", r.summary.mean_return},
                            {"mean_length", r.summary.mean_length},
                            {"success_rate", NullIfNegative(r.summary.success_rate)},
                            {"steps_per_s", r.steps_per_s},
                            {"episodes", r.summary.ToJson()["episodes"]}});
  }
  table.Print(std::cout);

  const fs::path out_dir = config.out_dir;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw Error("cannot create output directory '" + out_dir.string() + "': " + ec.message());
  AtomicWriteFile(out_dir / "config.yaml", DumpYaml(config.ToJson()));
  AtomicWriteFile(out_dir / "results.json",
                  nlohmann::json{{"config", config.ToJson()}, {"results", json_results}}.dump(2) +
                      "\n");
  AtomicWriteFile(out_dir / "results.csv", ResultsCsv(results, config.episodes));
  std::cerr << "demo: wrote " << (out_dir / "config.yaml").string()
            << ", results.json, results.csv\n";
}

}  // namespace

void AddDemoCommand(CLI::App& app, CommandContext& context) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "Random-policy rollouts over the configured envs; writes config.yaml, "
              "results.json and results.csv");
  cmd->add_option("args", args->positional,
                  "[CONFIG] [key=value ...]: a YAML file (default configs/demo.yaml) and "
                  "Hydra-style overrides such as episodes=3 envs=[cartpole,bandit]");
  cmd->add_option("--out", args->out, "output directory (overrides out_dir)");
  cmd->callback([args, &context] { RunDemo(*args, context); });
}

}  // namespace manyworlds::cli
