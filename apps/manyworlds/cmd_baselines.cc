// manyworlds baselines bandit|tabular-mdp RUN_DIR [...] [--json]: classical
// strategies (classic/bandit_baselines.h, classic/tabular_mdp_baselines.h)
// on the tasks of a run (its held-out eval_tasks.json, else tasks.json), the
// figures an RL2 result on that family is read against.
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "manyworlds/classic/bandit_baselines.h"
#include "manyworlds/classic/tabular_mdp_baselines.h"
#include "manyworlds/core/error.h"

namespace manyworlds::cli {
namespace {

namespace fs = std::filesystem;

struct BaselinesArgs {
  std::string run_dir;
  int64_t pulls = 10;     // bandit: pulls per trial
  int64_t episodes = 10;  // tabular-mdp: episodes per trial
  int64_t horizon = 10;   // tabular-mdp: steps per episode
  int64_t trials = 20;
  uint64_t seed = 1;
  bool json = false;
};

// The run's held-out task set if it has one, else its training set.
fs::path TasksFile(const std::string& run_dir) {
  const fs::path dir = run_dir;
  for (const char* name : {"eval_tasks.json", "tasks.json"}) {
    if (fs::is_regular_file(dir / name)) return dir / name;
  }
  throw ConfigError("'" + run_dir + "' is not a run directory (no tasks.json)");
}

// The `params` of every variation of a task set file (TaskSet::ToJson
// layout), each checked to come from `env` and to hold `keys`.
std::vector<nlohmann::json> VariationParams(const fs::path& file, const std::string& env,
                                            const std::vector<std::string>& keys) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json json = nlohmann::json::parse(text.str(), nullptr, false);
  if (json.is_discarded() || !json.is_object() || !json.contains("tasks") ||
      !json["tasks"].is_array()) {
    throw ConfigError(file.string() + ": not a task set");
  }
  std::vector<nlohmann::json> params;
  for (const auto& task : json["tasks"]) {
    for (const auto& v : task.value("variations", nlohmann::json::array())) {
      bool fits = v.value("env", "") == env && v.contains("params") && v["params"].is_object();
      for (const std::string& key : keys) fits = fits && v["params"].contains(key);
      if (!fits) {
        throw ConfigError(file.string() + ": not a " + env + " run (task '" +
                          task.value("name", "?") + "' runs " + v.value("env", "?") + ")");
      }
      params.push_back(v["params"]);
    }
  }
  return params;
}

// Runs every strategy and prints a table (or JSON with `extra` fields).
void Report(const std::vector<std::string>& names,
            const std::function<classic::BaselineResult(const std::string&)>& run,
            const BaselinesArgs& args, const fs::path& file, nlohmann::json extra,
            const std::string& heading) {
  nlohmann::json rows = nlohmann::json::array();
  Table table({"strategy", ">trial return", ">std. error"});
  for (const std::string& name : names) {
    const classic::BaselineResult r = run(name);
    rows.push_back({{"strategy", name},
                    {"trial_return", r.mean_trial_return},
                    {"standard_error", r.standard_error}});
    table.AddRow({name, Fixed(r.mean_trial_return, 3), Fixed(r.standard_error, 3)});
  }
  if (args.json) {
    extra["tasks_file"] = file.string();
    extra["trials_per_task"] = args.trials;
    extra["baselines"] = rows;
    PrintJson(extra);
    return;
  }
  std::cout << file.string() << ": " << heading << ", " << args.trials << " trials each\n";
  table.Print(std::cout);
}

void RunBanditBaselines(const BaselinesArgs& args) {
  const fs::path file = TasksFile(args.run_dir);
  std::vector<std::vector<double>> tasks;
  for (const auto& p : VariationParams(file, "bandit", {"probs"})) {
    tasks.push_back(p["probs"].get<std::vector<double>>());
  }
  Report(
      classic::BanditBaselineNames(),
      [&](const std::string& name) {
        return classic::RunBanditBaseline(name, tasks, args.pulls, args.trials, args.seed);
      },
      args, file, {{"tasks", tasks.size()}, {"pulls", args.pulls}},
      std::to_string(tasks.size()) + " bandits, trials of " + std::to_string(args.pulls) +
          " pulls");
}

void RunTabularMdpBaselines(const BaselinesArgs& args) {
  const fs::path file = TasksFile(args.run_dir);
  std::vector<classic::TabularMdp> tasks;
  for (const auto& p :
       VariationParams(file, "tabular-mdp", {"n_states", "n_actions", "rewards", "transitions"})) {
    tasks.push_back({p["n_states"].get<int64_t>(), p["n_actions"].get<int64_t>(),
                     p["rewards"].get<std::vector<double>>(),
                     p["transitions"].get<std::vector<double>>()});
  }
  Report(
      classic::TabularMdpBaselineNames(),
      [&](const std::string& name) {
        return classic::RunTabularMdpBaseline(name, tasks, args.episodes, args.horizon, args.trials,
                                              args.seed);
      },
      args, file,
      {{"tasks", tasks.size()}, {"episodes", args.episodes}, {"horizon", args.horizon}},
      std::to_string(tasks.size()) + " MDPs, trials of " + std::to_string(args.episodes) +
          " episodes of " + std::to_string(args.horizon) + " steps");
}

CLI::Option* AddCount(CLI::App* app, const std::string& name, int64_t& value,
                      const std::string& help) {
  return app->add_option(name, value, help)
      ->check(CLI::Range(int64_t{1}, int64_t{1000000}))
      ->capture_default_str();
}

void AddCommon(CLI::App* app, BaselinesArgs& args, const std::string& family) {
  app->add_option("run_dir", args.run_dir, "a run on the " + family + " env")->required();
  AddCount(app, "--trials", args.trials, "trials per task");
  app->add_option("--seed", args.seed, "seed of the simulated trials")->capture_default_str();
  app->add_flag("--json", args.json, "print JSON instead of a table");
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
  AddCommon(bandit, *args, "bandit");
  AddCount(bandit, "--pulls", args->pulls, "pulls per trial (RL2's episodes per trial)");
  bandit->callback([args] { RunBanditBaselines(*args); });

  CLI::App* mdp = cmd->add_subcommand(
      "tabular-mdp",
      "random, greedy, epsilon-greedy, posterior sampling and the oracle on the MDPs of a run "
      "(its held-out eval_tasks.json, else tasks.json): mean total reward of a trial");
  AddCommon(mdp, *args, "tabular-mdp");
  AddCount(mdp, "--episodes", args->episodes, "episodes per trial (RL2's episodes_per_trial)");
  AddCount(mdp, "--horizon", args->horizon, "steps per episode (the env's horizon option)");
  mdp->callback([args] { RunTabularMdpBaselines(*args); });
}

}  // namespace manyworlds::cli
