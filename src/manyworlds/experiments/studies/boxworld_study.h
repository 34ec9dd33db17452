// The CS330 box-world study (Malde and Elabd 2022; docs/boxworld.md "The
// study"):
// every method trained and evaluated on the same generated worlds, one row
// per method with the paper's numbers beside ours.
//
//   StudyOptions options;  options.task = "simple";  options.out_dir = "runs/study";
//   std::vector<StudyRow> rows = RunBoxWorldStudy(options, callbacks);
//   WriteStudyTables(rows, options);   // table.json, table.csv, table.md in out_dir
//
// The protocol. Training worlds come from task seed 0 of box-world-<task>
// with targets_per_layout = 9: groups of 9 consecutive task draws share a
// layout (agent and box starts; on the broad distribution also floor and
// boxes) and differ in the target, the paper's kSupportTargets support +
// kQueryTargets query targets of a meta-training round (the configs'
// env.support_variations / query_variations: meta-learners adapt on a
// layout's support targets and are trained on its query targets). Test
// worlds: kTestLayouts new layouts (task seed kTestTaskSeed, which shares no
// layout with the training seed) with the same split. Every method is scored
// on the query targets of the test layouts (the oracle on its own training
// task):
//   oracle     PPO on one task, evaluated on that task
//   baseline   PPO on one (other) task, evaluated on the test query targets
//   finetune   the baseline's PPO fine-tuned on the first support target of
//              each of the kFinetuneTasks test layouts, evaluated on that
//              layout's query targets
//   multitask  PPO on all training worlds, evaluated on the test query targets
//   maml, pearl, rl2  trained on the training worlds; the meta-test protocol
//              on each test layout (exploration episodes on its support
//              targets, adaptation, one evaluation episode on each of its
//              query targets; only the evaluation episodes count)
// MT methods act deterministically; each test task is one episode (resets
// are deterministic). success = the episode earned the +100 (the env's
// `success`); mean and std of episode return over the scored episodes.
//
// Each method's configuration is configs/boxworld_<method>_<task>.yaml
// (options.config_dir); the study sets run_dir (out_dir/<method>), the seed,
// env options (target_in_obs, hide_target, the distribution) and scales
// steps_per_task by options.budget. A method whose out_dir/<method>/result.json
// exists is not run again (a killed study resumes); an unfinished run is
// resumed from its last checkpoint. Nothing here prints: progress goes to
// callbacks.
#ifndef MANYWORLDS_EXPERIMENTS_STUDIES_BOXWORLD_STUDY_H_
#define MANYWORLDS_EXPERIMENTS_STUDIES_BOXWORLD_STUDY_H_

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/error.h"
#include "manyworlds/experiments/task_set.h"
#include "manyworlds/experiments/trainer.h"

namespace manyworlds::experiments {

inline constexpr int64_t kSupportTargets = 5;
inline constexpr int64_t kQueryTargets = 4;
inline constexpr int64_t kTestLayouts = 4;
inline constexpr int64_t kFinetuneTasks = 4;
inline constexpr uint64_t kTestTaskSeed = 1000;

struct StudyOptions {
  std::string task = "simple";          // simple | complex
  double budget = 1.0;                  // multiplies every config's steps_per_task
  std::vector<std::string> methods;     // empty: the paper's six
  std::filesystem::path out_dir = "runs/study_boxworld";
  std::filesystem::path config_dir = "configs";
  bool hide_target = false;
  std::string distribution = "narrow";  // narrow | broad
  uint64_t seed = 1;
  // Start layout: "paper" (the agent in a corner, its box touching it in
  // front: box world options agent_start=corner, box_start_gap=0.1) or
  // "anywhere" (agent and boxes anywhere). Empty: the task's default,
  // StudyLayout.
  std::string layout;
};

// The study's code starts its agent at (0.55, 0.55) on its [0, 5]^2 floor and
// its cube at (0.75, 0.75), touching it (its env.py), so every push moves
// the cube toward the room, where every target is. The complex task keeps
// that layout: with boxes anywhere no method ever moved the box, and with the
// box beside the agent on a random side the first pushes usually move it
// away from the target, and PPO learns to keep off it (docs/boxworld.md "The
// complex task"). The simple task's box is an obstacle; everything starts
// anywhere.
inline constexpr double kPaperBoxStartGap = 0.1;
std::string StudyLayout(const StudyOptions& options);

// Published numbers (PaperResult); absent for methods the paper did not run.
struct PaperNumbers {
  double mean_reward = 0.0;
  double std_reward = 0.0;
  double success = 0.0;  // fraction
};

struct StudyRow {
  std::string method;
  int64_t episodes = 0;        // scored episodes
  double mean_reward = 0.0;
  double std_reward = 0.0;     // population std over the scored episodes
  double success = 0.0;        // fraction of scored episodes with success
  int64_t train_env_steps = 0; // env steps of training, all envs and runs
  double wall_s = 0.0;         // training and evaluation, all sessions
  std::optional<PaperNumbers> paper;
  nlohmann::json ToJson() const;
  static StudyRow FromJson(const nlohmann::json& json);
};

struct StudyProgress {
  std::string method;
  int64_t method_index = 0;  // in [0, num_methods)
  int64_t num_methods = 0;
  std::string phase;         // "train", "train task k/n" (finetune), "evaluate"
  TrainProgress train;       // of the running training run
};

struct StudyCallbacks {
  std::function<void(const StudyProgress&)> on_progress;
  std::function<void(const StudyRow&, bool reused)> on_row;  // reused: from result.json
  // polled between training iterations and before each evaluation
  std::function<bool()> stop_requested;
};

// Thrown by RunBoxWorldStudy when stop_requested said so: the running training run has
// checkpointed, finished methods have their result.json, and the same call resumes.
class StudyStopped : public Error {
 public:
  using Error::Error;
};

// The methods in table order: the paper's six, then rl2.
const std::vector<std::string>& StudyMethods();
const std::vector<std::string>& PaperMethods();
// The published numbers of a method on options.task, read from
// PublishedResultsFile (configs/published/boxworld_study.yaml: the paper's
// Tables 1-2); nothing for a method the paper did not run or without the
// file. ConfigError naming the entry if it is malformed.
std::filesystem::path PublishedResultsFile(const StudyOptions& options);
std::optional<PaperNumbers> PaperResult(const StudyOptions& options, const std::string& method);

// ConfigError (one line) for a bad task, method, distribution or budget.
void ValidateStudyOptions(const StudyOptions& options);

// The env options every method's worlds use: target_in_obs, hide_target and,
// on the broad distribution, floor size and box count ranges.
nlohmann::json StudyEnvOptions(const StudyOptions& options);
// The test tasks (kTestLayouts layouts x (kSupportTargets + kQueryTargets)
// targets, one task of that many variations, consecutive groups sharing a
// layout, with the support/query split).
EnvSectionConfig StudyTestSection(const StudyOptions& options);
// A method's training config as the study runs it (config file, then the
// study's settings). `run_dir` overrides out_dir/<method>.
TrainConfig StudyMethodConfig(const StudyOptions& options, const std::string& method);

// Runs (or resumes) every method and returns one row per method, in table
// order. Throws ConfigError for bad options or configs, Error when a run
// fails; a stop request ends the study early with Error("stopped").
std::vector<StudyRow> RunBoxWorldStudy(const StudyOptions& options,
                                       const StudyCallbacks& callbacks = {});

// The table as JSON ({"task", "distribution", "hide_target", "budget",
// "seed", "rows": [...]}), CSV (one line per row) and markdown.
nlohmann::json StudyTableJson(const std::vector<StudyRow>& rows, const StudyOptions& options);
std::string StudyTableCsv(const std::vector<StudyRow>& rows);
std::string StudyTableMarkdown(const std::vector<StudyRow>& rows, const StudyOptions& options);
// Writes table.json, table.csv and table.md into options.out_dir.
void WriteStudyTables(const std::vector<StudyRow>& rows, const StudyOptions& options);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_STUDIES_BOXWORLD_STUDY_H_
