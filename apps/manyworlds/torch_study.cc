// manyworlds study boxworld [--task simple|complex] [--budget X] [--methods a,b] [--out DIR]
//                           [--hide-target] [--distribution narrow|broad] [--seed N]
//                           [--layout paper|anywhere]
//
// The CS330 box-world study (experiments/studies/boxworld_study.h): trains and evaluates every
// method, then prints the table (ours beside the paper's) and writes it as table.json,
// table.csv and table.md into the output directory. stderr gets a progress line.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "apps/manyworlds/cli_util.h"
#include "apps/manyworlds/commands.h"
#include "apps/manyworlds/remaining_time.h"
#include "apps/manyworlds/stop_signals.h"
#include "manyworlds/core/error.h"
#include "manyworlds/experiments/studies/boxworld_study.h"
#include "manyworlds/experiments/trainer.h"

namespace manyworlds::cli {
namespace {

namespace fs = std::filesystem;
using experiments::StudyOptions;

struct StudyArgs {
  StudyOptions options;
  std::string methods;
  std::string out;
  bool json = false;
};

// One redrawn status line on stderr (as `train`'s): the method, its phase,
// the running run's steps, bar, env steps/s and ETA.
class StudyStatus {
 public:
  explicit StudyStatus(bool force) : enabled_(line_.tty() || force) {}

  void Update(const experiments::StudyProgress& p) {
    if (!enabled_) return;
    const auto now = Steady::now();
    if (p.phase != phase_ || p.method != method_) {
      phase_ = p.phase;
      method_ = p.method;
      remaining_.Reset();
    } else if (now - last_ <
               (line_.tty() ? std::chrono::milliseconds(100) : std::chrono::seconds(5))) {
      return;
    }
    last_ = now;
    std::string line = "study " + std::to_string(p.method_index + 1) + "/" +
                       std::to_string(p.num_methods) + " " + p.method + " " + p.phase;
    if (p.train.total_steps > 0) {
      const double fraction =
          static_cast<double>(p.train.step) / static_cast<double>(p.train.total_steps);
      const double eta = remaining_.Update(static_cast<double>(p.train.step),
                                           static_cast<double>(p.train.total_steps), now);
      line += " " + Human(static_cast<double>(p.train.step)) + "/" +
              Human(static_cast<double>(p.train.total_steps)) + " steps/env " + Bar(fraction) + " " +
              Human(p.train.env_steps_per_s) + " env steps/s ETA " + FormatDuration(eta);
    }
    line_.Write(line);
  }

  void Note(const std::string& text) {
    if (enabled_) line_.Note(text);
  }

 private:
  using Steady = std::chrono::steady_clock;

  StatusLine line_;
  bool enabled_;
  std::string phase_, method_;
  Steady::time_point last_{};
  RemainingTime remaining_;
};

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    if (item.empty()) throw ConfigError("--methods: empty name in '" + text + "'");
    items.push_back(item);
  }
  return items;
}

void RunStudy(StudyArgs& args, CommandContext& context) {
  StudyOptions& o = args.options;
  if (!args.methods.empty()) o.methods = SplitList(args.methods);
  o.out_dir = args.out.empty() ? fs::path("runs") / ("study_boxworld_" + o.task +
                                                      (o.distribution == "broad" ? "_broad" : "") +
                                                      (o.hide_target ? "_hidden" : ""))
                               : fs::path(args.out);
  experiments::ValidateStudyOptions(o);
  StudyStatus status(context.progress);
  status.Note("study: box-world-" + o.task + ", " + o.distribution + " distribution, target " +
              (o.hide_target ? "hidden" : "observed") + ", budget x" + Fixed(o.budget, 3) +
              ", runs in " + o.out_dir.string());
  experiments::StudyCallbacks callbacks;
  callbacks.on_progress = [&](const experiments::StudyProgress& p) { status.Update(p); };
  callbacks.on_row = [&](const experiments::StudyRow& row, bool reused) {
    status.Note("study: " + row.method + (reused ? " (finished earlier)" : "") + ": success " +
                Fixed(100 * row.success, 1) + " %, mean reward " + Fixed(row.mean_reward, 2) +
                " over " + std::to_string(row.episodes) + " episodes");
  };
  const StopSignals signals;
  callbacks.stop_requested = [] { return StopSignals::received() != 0; };
  const auto start = std::chrono::steady_clock::now();
  std::vector<experiments::StudyRow> rows;
  try {
    rows = experiments::RunBoxWorldStudy(o, callbacks);
  } catch (const experiments::StudyStopped& e) {
    // as train: a signal stops at the next safe point, and the exit code is 128 + the signal
    status.Note(std::string("study: ") + (StopSignals::received() ? "interrupted; " : "") +
                e.what());
    context.exit_code = StopSignals::received() ? StopSignals::exit_code() : 1;
    return;
  }
  experiments::WriteStudyTables(rows, o);
  // a signal during the last evaluation: the tables are complete and written, and the exit
  // code still says the command was interrupted
  if (StopSignals::received()) context.exit_code = StopSignals::exit_code();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (args.json) {
    PrintJson(experiments::StudyTableJson(rows, o));
  } else {
    std::cout << experiments::StudyTableMarkdown(rows, o);
  }
  status.Note("study: done in " + FormatDuration(wall) + " (this session); tables in " +
              (o.out_dir / "table.{json,csv,md}").string());
}

}  // namespace

void AddStudyCommand(CLI::App& app, CommandContext& context) {
  CLI::App* study = app.add_subcommand(
      "study", "Reproduce a published study on this project's envs (one so far: boxworld)");
  study->require_subcommand(1);
  auto args = std::make_shared<StudyArgs>();
  CLI::App* cmd = study->add_subcommand(
      "boxworld",
      "The CS330 box-world study (Malde and Elabd 2022): oracle, baseline, finetune, "
      "multitask, maml, pearl (and rl2) trained and evaluated on generated box worlds; prints "
      "mean reward, std, success per method beside the paper's numbers and writes "
      "table.json, table.csv, table.md. A killed study resumes: finished methods are not run "
      "again. docs/boxworld.md, section 'The study'");
  cmd->add_option("--task", args->options.task, "simple (reach the target) or complex (push "
                  "the box to it)")
      ->capture_default_str();
  cmd->add_option("--budget", args->options.budget,
                  "factor on every method's training steps (1 = the configs' budgets: the "
                  "simple task in under an hour on two cores)")
      ->capture_default_str();
  cmd->add_option("--methods", args->methods,
                  "comma-separated subset of oracle, baseline, finetune, multitask, maml, "
                  "pearl, rl2 (default: the paper's six)");
  cmd->add_option("--out", args->out,
                  "output directory: one run directory per method and the tables (default "
                  "runs/study_boxworld_<task>[_broad][_hidden])");
  cmd->add_option("--configs", args->options.config_dir,
                  "directory of the methods' configs boxworld_<method>_<task>.yaml")
      ->capture_default_str();
  cmd->add_flag("--hide-target", args->options.hide_target,
                "zero the target in the observation (infer it from rewards)");
  cmd->add_option("--distribution", args->options.distribution,
                  "narrow: the paper's 5 m floor and one box, layouts and targets vary; broad: "
                  "floor 4-8 m and 1-3 boxes of three shapes vary too")
      ->capture_default_str();
  cmd->add_option("--seed", args->options.seed, "seed of every run and evaluation")
      ->capture_default_str();
  cmd->add_option("--layout", args->options.layout,
                  "paper: the agent starts in a corner with its box touching it in front, as "
                  "the paper's code; anywhere: agent and boxes start anywhere (default: "
                  "complex paper, simple anywhere)");
  cmd->add_flag("--json", args->json, "print the table as JSON instead of markdown");
  cmd->callback([args, &context] {
    experiments::NameMemorySettingsOnFailure([&] { RunStudy(*args, context); });
  });
}

}  // namespace manyworlds::cli
