// manyworlds train CONFIG.yaml [key=value ...] | --resume RUN_DIR
// manyworlds eval RUN_DIR [--episodes N] [--checkpoint latest|step_N|DIR] [--json]
// manyworlds eval CONFIG.yaml --policy scripted|random [--seed N] (the protocols, no run)
// manyworlds rollout --policy checkpoint:RUN_DIR (RunCheckpointRollout)
//
// Training and evaluation of every registered algorithm (experiments/trainer.h). Results
// go to the run directory; stdout gets the per-task success table (or JSON);
// stderr gets a progress line when it is a terminal or with --progress.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "apps/manyworlds/remaining_time.h"
#include "apps/manyworlds/stop_signals.h"
#include "manyworlds/config/override.h"
#include "manyworlds/core/error.h"
#include "manyworlds/experiments/algorithms.h"
#include "manyworlds/experiments/evaluation/policy_actor.h"
#include "manyworlds/experiments/run/checkpoint_integrity.h"
#include "manyworlds/experiments/run/run_dir.h"
#include "manyworlds/experiments/trainer.h"
#include "manyworlds/nn/threads.h"

namespace manyworlds::cli {
namespace {

namespace fs = std::filesystem;
using experiments::EvalResult;

std::string Success(const std::optional<double>& rate) {
  return rate ? Fixed(*rate, 2) : "-";
}

std::string OptionalFixed(const nlohmann::json& v, int digits) {
  return v.is_number() ? Fixed(v.get<double>(), digits) : std::string("-");
}

// A meta-test result (MetaTestResult::ToJson) as a table; `what` is
// "meta-test" (held-out tasks) or "meta-train" (training tasks).
void PrintMetaTestTable(const nlohmann::json& m, std::ostream& out,
                        const std::string& what = "meta-test") {
  Table table({what == "meta-test" ? "test task" : "train task", ">success", ">return", ">success before", ">return before",
               ">trial return"});
  for (const auto& [name, t] : m["per_task"].items()) {
    table.AddRow({name, OptionalFixed(t["success"], 2), OptionalFixed(t["return"], 2),
                  OptionalFixed(t["pre_adaptation_success"], 2),
                  OptionalFixed(t["pre_adaptation_return"], 2),
                  OptionalFixed(t["trial_return"], 2)});
  }
  table.AddRow({"mean", OptionalFixed(m["success_rate"], 2), OptionalFixed(m["return"], 2),
                OptionalFixed(m["pre_adaptation_success_rate"], 2),
                OptionalFixed(m["pre_adaptation_return"], 2), OptionalFixed(m["trial_return"], 2)});
  out << what << ": "
      << experiments::DescribeProtocol(experiments::MetaTestConfigOf(m))
      << "\n";
  table.Print(out);
}

void PrintEvalTable(const EvalResult& eval, std::ostream& out) {
  Table table({"task", ">success", ">return", ">length"});
  for (const auto& t : eval.per_task) {
    table.AddRow({t.task, Success(t.success), Fixed(t.mean_return, 2), Fixed(t.mean_length, 1)});
  }
  table.AddRow({"mean", Success(eval.mean_success), Fixed(eval.mean_return, 2), ""});
  table.Print(out);
}

// One redrawn status line on stderr: on a terminal at most 10 times a
// second, otherwise (with --progress) one line every 2 seconds; notes
// (resume, evaluations) always.
class TrainStatus {
 public:
  explicit TrainStatus(bool force) : enabled_(line_.tty() || force) {}

  void Update(const experiments::TrainProgress& p) {
    if (!enabled_) return;
    const auto now = Clock::now();
    const bool done = p.step >= p.total_steps;
    if (!done &&
        now - last_ < (line_.tty() ? std::chrono::milliseconds(100) : std::chrono::seconds(2))) {
      return;
    }
    last_ = now;
    const double fraction =
        p.total_steps > 0 ? static_cast<double>(p.step) / static_cast<double>(p.total_steps) : 1;
    const double eta = remaining_.Update(static_cast<double>(p.step),
                                         static_cast<double>(p.total_steps), now);
    std::string line = "train " + Human(static_cast<double>(p.step)) + "/" +
                       Human(static_cast<double>(p.total_steps)) + " steps " + Bar(fraction) + " " +
                       Human(p.env_steps_per_s) + " env steps/s " + Human(p.updates_per_s) +
                       " updates/s";
    if (p.last_eval) {
      line += p.last_eval->mean_success ? " success " + Fixed(*p.last_eval->mean_success, 2)
                                        : " return " + Fixed(p.last_eval->mean_return, 1);
    }
    line += " ETA " + FormatDuration(eta);
    line_.Write(line);
  }

  // Resume and evaluation lines always appear: one line per evaluation is
  // what a run in the background (nohup, a cluster job) should leave in its log.
  void Note(const std::string& text) { line_.Note(text); }

  // The time left is measured from here (after a resume, from the step it resumed at).
  void Start(const experiments::Trainer& trainer) {
    remaining_.Reset();
    remaining_.Update(static_cast<double>(trainer.step()), 0);
  }

 private:
  using Clock = std::chrono::steady_clock;

  StatusLine line_;
  bool enabled_;
  Clock::time_point last_{};
  RemainingTime remaining_;
};

struct TrainArgs {
  std::vector<std::string> positional;  // CONFIG then overrides
  std::string resume;
  bool restart = false;
  int64_t stop_after = -1;
  bool print_config = false;
};

void RunTrain(const TrainArgs& args, CommandContext& context) {
  std::optional<experiments::Trainer> trainer;
  if (!args.resume.empty()) {
    if (args.print_config) throw ConfigError("--print-config goes with CONFIG, not --resume");
    if (!args.positional.empty()) {
      throw ConfigError("--resume continues a run with its saved config; drop '" +
                        args.positional.front() + "'");
    }
    // a finished run stays as it is: resuming it again would rewrite its summary
    if (const auto step = experiments::FinishedRunStep(args.resume); step && !args.restart) {
      std::cerr << "train: " << args.resume << " finished at step " << *step
                << "; nothing to resume (its summary.json is unchanged)\n";
      return;
    }
    trainer.emplace(experiments::Trainer::Resume(args.resume, args.restart));
  } else {
    if (args.restart) throw ConfigError("--restart goes with --resume RUN_DIR");
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
    if (!file) {
      throw ConfigError("train needs a config file, e.g. `manyworlds train "
                        "configs/point_nav_sac.yaml`, or --resume RUN_DIR");
    }
    experiments::TrainConfig config = experiments::TrainConfig::Load(file, overrides);
    if (args.print_config) {
      // for tools that plan runs (the sweep layer): the resolved, validated config, nothing made
      config.Validate();
      PrintJson(config.ToJson());
      return;
    }
    trainer.emplace(experiments::Trainer::Create(config));
  }

  const std::string run_dir = trainer->run_dir().string();
  std::optional<TrainStatus> status_line(std::in_place, context.progress);
  TrainStatus& status = *status_line;
  status.Start(*trainer);
  for (const std::string& warning : trainer->warnings()) status.Note("warning: " + warning);
  if (trainer->step() == 0) {  // a resumed run must keep its thread count
    const std::string advice =
        nn::BlasContentionAdvice(nn::OneMinuteLoadAverage(), nn::CurrentThreads().blas_threads);
    if (!advice.empty()) status.Note("warning: " + advice);
  }
  if (trainer->step() > 0) {
    status.Note("train: resuming " + run_dir + " at step " + std::to_string(trainer->step()));
  }
  experiments::TrainCallbacks callbacks;
  callbacks.on_round = [&](const experiments::TrainProgress& p) { status.Update(p); };
  callbacks.on_eval = [&](const EvalResult& e) {
    status.Note("eval @ " + std::to_string(e.step) + ": success " + Success(e.mean_success) +
                ", return " + Fixed(e.mean_return, 2));
  };
  if (args.stop_after >= 0) callbacks.stop_after_step = args.stop_after;
  // Ctrl-C, SIGTERM, SIGHUP: finish the iteration, checkpoint, stop
  const StopSignals signals;
  callbacks.stop_requested = [] { return StopSignals::received() != 0; };
  const experiments::TrainSummary summary = trainer->Run(callbacks);
  status_line.reset();  // clears the status line

  if (summary.final_eval) PrintEvalTable(*summary.final_eval, std::cout);
  if (summary.final_meta_train) {
    PrintMetaTestTable(*summary.final_meta_train, std::cout, "meta-train");
  }
  if (summary.final_meta_test) PrintMetaTestTable(*summary.final_meta_test, std::cout);
  if (!summary.finished) {
    std::cerr << "train: " << (StopSignals::received() ? "interrupted; " : "") << "stopped at step "
              << summary.step << " after its checkpoint; continue with `manyworlds train --resume "
              << run_dir << "`\n";
    if (StopSignals::received()) context.exit_code = StopSignals::exit_code();
    return;
  }
  std::cerr << "train: " << run_dir << ": " << summary.step << " steps per env, "
            << summary.updates << " updates in " << FormatDuration(summary.wall_s) << " ("
            << Human(summary.env_steps_per_s) << " env steps/s, "
            << Human(summary.updates_per_s) << " updates/s this session)\n";
}

struct EvalArgs {
  std::string run_dir;
  std::string checkpoint = "latest";
  int64_t episodes = 0;
  std::string protocol = "multi-task";
  bool json = false;
  // an env policy (scripted, random) instead of a run: run_dir is then a config
  std::string policy;
  std::optional<uint64_t> seed;
  // meta_test keys the command line sets for this evaluation (empty: the run's)
  std::map<std::string, std::string> meta_test;
};

// The meta-test protocol's parameters eval takes, with v3's names
// (metaworld/evaluation.py), and what each is (the help names the protocol
// a key belongs to, MetaTestConfig::ProtocolOf).
const std::vector<std::pair<std::string, std::string>>& MetaTestOptions() {
  static const std::vector<std::pair<std::string, std::string>> options = {
      {"meta_protocol", "metalearning_evaluation (Meta-World v3's) or per_variation"},
      {"num_evals", "rounds, each on newly sampled goals"},
      {"adaptation_steps", "adaptation phases per round"},
      {"adaptation_episodes", "episodes per env and adaptation phase"},
      {"evaluation_episodes", "episodes after adaptation per task (per_variation: per trial)"},
      {"meta_batch_size", "envs, split evenly between the tasks"},
      {"total_tasks_per_cls", "goals per task, its first N (0: all)"},
      {"task_select", "random or pseudorandom goal per env and round"},
      {"terminate_on_success", "evaluation episodes end at success (true/false)"},
      {"exploration_episodes", "episodes per trial before adaptation"},
      {"trials_per_task", "variations tried per task"},
      {"sample_evaluation", "evaluation episodes sample instead of the mode (true/false)"},
  };
  return options;
}

// The config with its meta_test section as the command line changes it.
experiments::TrainConfig WithMetaTestOptions(experiments::TrainConfig config,
                                             const std::map<std::string, std::string>& set) {
  std::vector<std::string> overrides;
  for (const auto& [key, value] : set) {
    if (value.empty()) continue;
    overrides.push_back("meta_test." + (key == "meta_protocol" ? std::string("protocol") : key) +
                        "=" + value);
  }
  if (overrides.empty()) return config;
  nlohmann::json tree = config.ToJson();
  ApplyOverrides(tree, overrides);
  config.meta_test = experiments::TrainConfig::FromJson(tree).meta_test;
  config.meta_test.Validate();
  return config;
}



// snake_case -> kebab-case, for option names
std::string Dashed(std::string key) {
  std::replace(key.begin(), key.end(), '_', '-');
  return key;
}

// The checkpoint `which` names (latest: the newest intact one, with a
// warning per damaged newer one), verified before use.
fs::path FindCheckpoint(const fs::path& run_dir, const std::string& which) {
  if (which == "latest") {
    const experiments::ChosenCheckpoint chosen = experiments::ChooseCheckpoint(run_dir);
    for (const std::string& warning : chosen.warnings) std::cerr << "warning: " << warning << "\n";
    return chosen.dir;
  }
  const fs::path in_run = experiments::RunPaths{run_dir}.checkpoints() / which;
  for (const fs::path& dir : {in_run, fs::path(which)}) {
    if (fs::is_directory(dir)) {
      experiments::VerifyCheckpoint(dir, run_dir);
      return dir;
    }
  }
  std::string available;
  for (const fs::path& dir : experiments::ListCheckpoints(run_dir)) {
    available += (available.empty() ? "" : ", ") + dir.filename().string();
  }
  throw ConfigError("no checkpoint '" + which + "' in '" + run_dir.string() + "' (available: " +
                    (available.empty() ? "none" : available) + ", or 'latest')");
}

// Runs `use` on `checkpoint`, which FindCheckpoint(run_dir, which) chose. A run that is
// training prunes its old checkpoints (experiment.keep_checkpoints) as it writes new ones, so
// the latest may vanish (or be half removed) between its choice and its reading: when a newer
// one has appeared since, that one is chosen.
template <class F>
auto UsingCheckpoint(const fs::path& run_dir, const std::string& which, fs::path& checkpoint,
                     F&& use) {
  constexpr int kAttempts = 10;
  for (int attempt = 1;; ++attempt) {
    try {
      return use(checkpoint);
    } catch (const std::exception&) {
      if (which != "latest" || attempt == kAttempts) throw;
      const std::vector<fs::path> now = experiments::ListCheckpoints(run_dir);
      if (now.empty() || now.back() == checkpoint) throw;  // nothing newer to choose
      checkpoint = FindCheckpoint(run_dir, which);
    }
  }
}

// eval CONFIG --policy scripted|random: the config's protocols driven by the
// envs' own policies, no run needed.
void RunPolicyEval(const EvalArgs& args) {
  if (args.checkpoint != "latest") throw ConfigError("eval: --checkpoint needs a run, not --policy");
  const experiments::TrainConfig config = WithMetaTestOptions(
      experiments::TrainConfig::Load(fs::path(args.run_dir)), args.meta_test);
  const uint64_t seed = args.seed ? *args.seed : config.experiment.seed;
  if (args.protocol == "meta-test" || args.protocol == "meta-train") {
    const bool test = args.protocol == "meta-test";
    if (args.episodes > 0) {
      throw ConfigError("eval: --episodes is for the multi-task protocol; the " + args.protocol +
                        " episodes are the config's meta_test section");
    }
    const nlohmann::json result =
        experiments::MetaTestEnvPolicy(config, args.policy, seed, !test).ToJson();
    if (args.json) {
      PrintJson({{"policy", args.policy}, {test ? "meta_test" : "meta_train", result}});
      return;
    }
    std::cout << "policy " << args.policy << "\n";
    PrintMetaTestTable(result, std::cout, args.protocol);
    return;
  }
  const int64_t episodes = args.episodes > 0 ? args.episodes : config.experiment.eval_episodes;
  const EvalResult result = experiments::EvaluateEnvPolicy(config, args.policy, episodes, seed);
  if (args.json) {
    nlohmann::json json = result.ToJson();
    json["policy"] = args.policy;
    PrintJson(json);
    return;
  }
  std::cout << "policy " << args.policy << ", " << episodes << " episodes per task\n";
  PrintEvalTable(result, std::cout);
}

void RunEval(const EvalArgs& args, const CommandContext& context) {
  const bool meta = args.protocol == "meta-test" || args.protocol == "meta-train";
  for (const auto& [key, value] : args.meta_test) {
    if (!value.empty() && !meta) {
      throw ConfigError("eval: --" + Dashed(key) + " is an option of --protocol meta-test and "
                        "meta-train");
    }
  }
  if (!args.policy.empty()) {
    RunPolicyEval(args);
    return;
  }
  if (args.seed) throw ConfigError("eval: --seed is for --policy (a run's protocols use its seed)");
  experiments::RunInfo run = experiments::RunInfo::Read(args.run_dir);
  run.config = WithMetaTestOptions(run.config, args.meta_test);
  fs::path checkpoint = FindCheckpoint(args.run_dir, args.checkpoint);
  if (const auto warning = experiments::EvaluationThreadWarning(checkpoint)) {
    std::cerr << "warning: " << *warning << "\n";
  }
  if (args.protocol == "meta-test" || args.protocol == "meta-train") {
    const bool test = args.protocol == "meta-test";
    if (args.episodes > 0) {
      throw ConfigError("eval: --episodes is for the multi-task protocol; the " + args.protocol +
                        " episodes are the run's meta_test section");
    }
    if (context.progress || isatty(STDERR_FILENO)) {
      std::cerr << "eval: " << checkpoint.string() << ", " << args.protocol << " on "
                << (test ? "held-out" : "training") << " tasks, "
                << experiments::DescribeProtocol(run.config.meta_test) << "\n";
    }
    nlohmann::json result =
        UsingCheckpoint(args.run_dir, args.checkpoint, checkpoint, [&](const fs::path& chosen) {
          return test ? experiments::MetaTestCheckpoint(run, chosen)
                      : experiments::MetaTrainCheckpoint(run, chosen);
        });
    if (args.json) {
      PrintJson({{"checkpoint", checkpoint.string()}, {test ? "meta_test" : "meta_train", result}});
      return;
    }
    std::cout << "checkpoint " << checkpoint.filename().string() << " (step "
              << result["step"].get<int64_t>() << ")\n";
    PrintMetaTestTable(result, std::cout, args.protocol);
    return;
  }
  const int64_t episodes =
      args.episodes > 0 ? args.episodes : run.config.experiment.eval_episodes;
  if (context.progress || isatty(STDERR_FILENO)) {
    std::cerr << "eval: " << checkpoint.string() << ", " << episodes << " episodes per task\n";
  }
  const EvalResult result =
      UsingCheckpoint(args.run_dir, args.checkpoint, checkpoint, [&](const fs::path& chosen) {
        return experiments::EvaluateCheckpoint(run, chosen, episodes);
      });
  if (args.json) {
    nlohmann::json json = result.ToJson();
    json["checkpoint"] = checkpoint.string();
    PrintJson(json);
    return;
  }
  std::cout << "checkpoint " << checkpoint.filename().string() << " (step " << result.step
            << "), " << episodes << " episodes per task\n";
  PrintEvalTable(result, std::cout);
}

// A meta-RL run (one with held-out tasks): `trials` trials per held-out
// task, each of the run's exploration episodes, adaptation, then its
// evaluation episodes, one row per episode.
void PrintMetaLearnerRollout(const fs::path& run_dir, const fs::path& checkpoint,
                             const experiments::MetaTestResult& result, int trials,
                             uint64_t seed, bool json) {
  auto success = [](const std::optional<bool>& s) {
    return s ? nlohmann::json(*s) : nlohmann::json();
  };
  if (json) {
    nlohmann::json episodes = nlohmann::json::array();
    for (const auto& e : result.episodes) {
      episodes.push_back({{"task", e.task},
                          {"trial", e.trial},
                          {"phase", e.evaluation ? "evaluation" : "exploration"},
                          {"episode", e.index},
                          {"return", e.episode_return},
                          {"length", e.length},
                          {"success", success(e.success)}});
    }
    PrintJson({{"checkpoint", checkpoint.string()},
               {"step", result.step},
               {"seed", seed},
               {"episodes", episodes},
               {"meta_test", result.ToJson()}});
    return;
  }
  std::vector<experiments::MetaTestEpisode> rows = result.episodes;
  std::stable_sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
    return std::tie(a.task, a.trial, a.evaluation, a.index) <
           std::tie(b.task, b.trial, b.evaluation, b.index);
  });
  Table table({"held-out task", ">trial", "phase", ">episode", ">return", ">length", "success"});
  for (const auto& e : rows) {
    table.AddRow({e.task, std::to_string(e.trial), e.evaluation ? "adapted" : "explore",
                  std::to_string(e.index), Fixed(e.episode_return, 3), std::to_string(e.length),
                  e.success ? (*e.success ? "yes" : "no") : "-"});
  }
  table.Print(std::cout);
  std::cout << run_dir.string() << " (" << checkpoint.filename().string() << ", step "
            << result.step << "): " << trials << " trial(s) per held-out task of "
            << result.config.exploration_episodes << " exploration + "
            << result.config.evaluation_episodes << " adapted episodes; return "
            << Fixed(result.pre_adaptation_return, 3) << " before, " << Fixed(result.mean_return, 3)
            << " after adaptation";
  if (result.success_rate) {
    std::cout << ", success " << Success(result.pre_adaptation_success_rate) << " before, "
              << Success(result.success_rate) << " after";
  }
  std::cout << "\n";
}

}  // namespace

void RunCheckpointRollout(const std::string& path, const std::string& env_id, int episodes,
                          uint64_t seed, bool json) {
  // PATH is a run directory, or a checkpoint inside one (RUN/checkpoints/step_N)
  fs::path run_dir = path, checkpoint;
  if (fs::exists(fs::path(path) / "state.json") && !fs::exists(fs::path(path) / "config.yaml")) {
    checkpoint = path;
    run_dir = fs::path(path).parent_path().parent_path();
  }
  const experiments::RunInfo run = experiments::RunInfo::Read(run_dir);
  const std::string which = checkpoint.empty() ? "latest" : checkpoint.string();
  if (checkpoint.empty()) {
    checkpoint = FindCheckpoint(run_dir, "latest");
  } else {
    experiments::VerifyCheckpoint(checkpoint, run_dir);
  }
  if (!env_id.empty() && env_id != run.config.env.id) {
    throw ConfigError("rollout: --env '" + env_id + "' is not the env of run '" +
                      run_dir.string() + "' ('" + run.config.env.id +
                      "'); leave --env out to use the run's");
  }
  if (run.eval_tasks) {
    const experiments::MetaTestResult result =
        UsingCheckpoint(run_dir, which, checkpoint, [&](const fs::path& chosen) {
          return experiments::MetaTestCheckpointEpisodes(run, chosen, episodes, seed);
        });
    PrintMetaLearnerRollout(run_dir, checkpoint, result, episodes, seed, json);
    return;
  }
  const EvalResult result = UsingCheckpoint(run_dir, which, checkpoint, [&](const fs::path& c) {
    return experiments::EvaluateCheckpoint(run, c, episodes, seed);
  });
  if (json) {
    nlohmann::json tasks = nlohmann::json::array();
    for (const auto& t : result.per_task) {
      nlohmann::json rows = nlohmann::json::array();
      for (const auto& e : t.episodes) {
        rows.push_back({{"return", e.episode_return},
                        {"length", e.length},
                        {"success", e.success ? nlohmann::json(*e.success) : nlohmann::json()}});
      }
      tasks.push_back({{"task", t.task},
                       {"episodes", rows},
                       {"mean_return", t.mean_return},
                       {"success_rate", t.success ? nlohmann::json(*t.success) : nlohmann::json()}});
    }
    PrintJson({{"checkpoint", checkpoint.string()},
               {"step", result.step},
               {"seed", seed},
               {"tasks", tasks},
               {"mean_return", result.mean_return},
               {"success_rate", result.mean_success ? nlohmann::json(*result.mean_success)
                                                    : nlohmann::json()}});
    return;
  }
  Table table({"task", ">episode", ">return", ">length", "success"});
  for (const auto& t : result.per_task) {
    for (size_t i = 0; i < t.episodes.size(); ++i) {
      const auto& e = t.episodes[i];
      table.AddRow({t.task, std::to_string(i), Fixed(e.episode_return, 3),
                    std::to_string(e.length), e.success ? (*e.success ? "yes" : "no") : "-"});
    }
  }
  table.Print(std::cout);
  std::cout << run_dir.string() << " (" << checkpoint.filename().string() << ", step "
            << result.step << "): " << result.per_task.size() << " tasks x " << episodes
            << " episodes, mean return " << Fixed(result.mean_return, 3) << ", success rate "
            << Success(result.mean_success) << "\n";
}

void AddTrainCommand(CLI::App& app, CommandContext& context) {
  auto args = std::make_shared<TrainArgs>();
  CLI::App* cmd = app.add_subcommand(
      "train", "Train any registered algorithm (agent.algo: " + experiments::AlgorithmNames() +
                   "); writes config.yaml, metrics, evaluations, checkpoints and summary.json "
                   "into the run directory");
  cmd->add_option("args", args->positional,
                  "CONFIG [key=value ...]: a YAML file (see configs/) and Hydra-style "
                  "overrides such as experiment.seed=2 agent.hidden_dim=64");
  cmd->add_option("--resume", args->resume,
                  "continue the run in this directory from its latest checkpoint");
  cmd->add_flag("--restart", args->restart,
               "with --resume, for a run with no intact checkpoint: train it again from step 0 "
               "with its saved config (damaged checkpoints are kept as checkpoints.damaged.N)");
  cmd->add_option("--stop-after", args->stop_after,
                  "stop after the first checkpoint at or past this many steps per env "
                  "(continue later with --resume)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--print-config", args->print_config,
                "print the resolved config (defaults, file, overrides; validated) as JSON and "
                "exit without training or writing anything");
  cmd->callback([args, &context] {
    experiments::NameMemorySettingsOnFailure([&] { RunTrain(*args, context); });
  });
}

void AddEvalCommand(CLI::App& app, CommandContext& context) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "Evaluate a saved run: per-task success rate and return, by the multi-task "
              "protocol or (--protocol meta-test|meta-train) the meta-test protocol");
  cmd->add_option("run_dir", args->run_dir,
                  "the run directory (with --policy: a training config, whose tasks and "
                  "protocols are used)")
      ->required();
  cmd->add_option("--policy", args->policy,
                  "evaluate an env policy instead of a run: scripted (each env's expert) or "
                  "random (uniform actions, a stream per env); RUN_DIR is then a config file")
      ->check(CLI::IsMember(PolicyNames()));
  cmd->add_option("--seed", args->seed,
                  "with --policy: the protocol's and the random policy's seed (default: the "
                  "config's experiment.seed)");
  cmd->add_option("--episodes", args->episodes,
                  "episodes per task (default: the run's experiment.eval_episodes)")
      ->check(AtLeastOne(1000000));
  cmd->add_option("--checkpoint", args->checkpoint,
                  "'latest', a checkpoint name (step_...) or a checkpoint directory");
  cmd->add_option("--protocol", args->protocol,
                  "multi-task: the training tasks, deterministic episodes; meta-test: the "
                  "run's held-out tasks (eval_env) by the run's meta_test section (Meta-World "
                  "v3's metalearning_evaluation unless it says per_variation), which the "
                  "options below change; meta-train: the same protocol on the training tasks")
      ->check(CLI::IsMember({"multi-task", "meta-test", "meta-train"}))
      ->capture_default_str();
  for (const auto& [key, help] : MetaTestOptions()) {
    const std::string_view owner = experiments::MetaTestConfig::ProtocolOf(key);
    cmd->add_option("--" + Dashed(key), args->meta_test[key],
                    (owner.empty() ? "" : std::string(owner) + ": ") + help +
                        " (default: the run's meta_test." +
                        (key == "meta_protocol" ? std::string("protocol") : key) + ")");
  }
  cmd->add_flag("--json", args->json,
                "print JSON ({per_task, mean_success, mean_return, ...}; with meta-test "
                "{meta_test: {success_rate, per_task, pre_adaptation_success_rate, ...}}, "
                "with meta-train {meta_train: {...}}) "
                "instead of a table");
  cmd->callback([args, &context] {
    experiments::NameMemorySettingsOnFailure([&] { RunEval(*args, context); });
  });
}

}  // namespace manyworlds::cli
