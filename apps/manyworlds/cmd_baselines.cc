// manyworlds baselines bandit RUN_DIR [--pulls 10] [--trials 20] [--seed 1]
// [--json]: the classical bandit strategies (classic/bandit_baselines.h) on
// the bandits of a run (its held-out eval_tasks.json, else tasks.json), the
// figures an RL2 bandit result is read against.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "manyworlds/classic/bandit_baselines.h"
#include "manyworlds/core/error.h"

namespace manyworlds::cli {
namespace {

namespace fs = std::filesystem;

struct BaselinesArgs {
  std::string run_dir;
  int64_t pulls = 10;
  int64_t trials = 20;
  uint64_t seed = 1;
  bool json = false;
};

// Every bandit variation of a task set file (TaskSet::ToJson layout).
std::vector<std::vector<double>> BanditTasks(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json json = nlohmann::json::parse(text.str(), nullptr, false);
  if (json.is_discarded() || !json.is_object() || !json.contains("tasks")) {
    throw Error(file.string() + ": not a task set");
  }
  std::vector<std::vector<double>> probs;
  for (const auto& task : json["tasks"]) {
    for (const auto& v : task.value("variations", nlohmann::json::array())) {
      if (v.value("env", "") != "bandit" || !v.contains("params") ||
          !v["params"].contains("probs")) {
        throw ConfigError(file.string() + ": not a bandit run (task '" +
                          task.value("name", "?") + "' runs " + v.value("env", "?") + ")");
      }
      probs.push_back(v["params"]["probs"].get<std::vector<double>>());
    }
  }
  return probs;
}

void RunBanditBaselines(const BaselinesArgs& args) {
  const fs::path dir = args.run_dir;
  fs::path file = dir / "eval_tasks.json";
  if (!fs::exists(file)) file = dir / "tasks.json";
  if (!fs::exists(file)) {
    throw ConfigError("'" + args.run_dir + "' is not a run directory (no tasks.json)");
  }
  const std::vector<std::vector<double>> tasks = BanditTasks(file);
  nlohmann::json rows = nlohmann::json::array();
  Table table({"strategy", ">trial return", ">std. error"});
  for (const std::string& name : classic::BanditBaselineNames()) {
    const classic::BanditBaselineResult r =
        classic::RunBanditBaseline(name, tasks, args.pulls, args.trials, args.seed);
    rows.push_back({{"strategy", name},
                    {"trial_return", r.mean_trial_return},
                    {"standard_error", r.standard_error}});
    table.AddRow({name, Fixed(r.mean_trial_return, 3), Fixed(r.standard_error, 3)});
  }
  if (args.json) {
    PrintJson({{"tasks_file", file.string()},
               {"tasks", tasks.size()},
               {"pulls", args.pulls},
               {"trials_per_task", args.trials},
               {"baselines", rows}});
    return;
  }
  std::cout << file.string() << ": " << tasks.size() << " bandits, trials of " << args.pulls
            << " pulls, " << args.trials << " trials each\n";
  table.Print(std::cout);
}

}  // namespace

void AddBaselinesCommand(CLI::App& app, CommandContext&) {
  CLI::App* cmd = app.add_subcommand(
      "baselines", "Classical strategies on a run's tasks, to read meta-RL results against");
  cmd->require_subcommand(1);
  auto args = std::make_shared<BaselinesArgs>();
  CLI::App* bandit = cmd->add_subcommand(
      "bandit", "random, greedy, UCB1 and Thompson sampling on the bandits of a run (its "
                "held-out eval_tasks.json, else tasks.json): mean total reward of a trial");
  bandit->add_option("run_dir", args->run_dir, "a run on the bandit env")->required();
  bandit->add_option("--pulls", args->pulls, "pulls per trial (RL2's episodes per trial)")
      ->check(CLI::Range(int64_t{1}, int64_t{1000000}))
      ->capture_default_str();
  bandit->add_option("--trials", args->trials, "trials per bandit")
      ->check(CLI::Range(int64_t{1}, int64_t{1000000}))
      ->capture_default_str();
  bandit->add_option("--seed", args->seed, "seed of the simulated pulls")->capture_default_str();
  bandit->add_flag("--json", args->json, "print JSON instead of a table");
  bandit->callback([args] { RunBanditBaselines(*args); });
}

}  // namespace manyworlds::cli
