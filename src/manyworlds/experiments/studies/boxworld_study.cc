#include "manyworlds/experiments/studies/boxworld_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "manyworlds/config/reader.h"
#include "manyworlds/config/yaml.h"
#include "manyworlds/core/atomic_file.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"
#include "manyworlds/experiments/evaluation/meta_test_protocol.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Seed stream of the study's final evaluations (mixed with options.seed).
constexpr uint64_t kStudyEvalStream = 0x7374756479;  // "study"

// One scored episode.
struct Scored {
  double episode_return = 0.0;
  bool success = false;
};

bool IsMetaMethod(const std::string& method) {
  return method == "maml" || method == "pearl" || method == "rl2";
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string text;
  for (const auto& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

std::string EnvId(const StudyOptions& options) { return "box-world-" + options.task; }

StudyRow RowFrom(const std::string& method, const std::vector<Scored>& episodes) {
  StudyRow row;
  row.method = method;
  row.episodes = static_cast<int64_t>(episodes.size());
  if (episodes.empty()) throw Error("study: method '" + method + "' scored no episodes");
  double sum = 0.0, successes = 0.0;
  for (const auto& e : episodes) {
    sum += e.episode_return;
    successes += e.success ? 1.0 : 0.0;
  }
  row.mean_reward = sum / static_cast<double>(episodes.size());
  double sq = 0.0;
  for (const auto& e : episodes) sq += (e.episode_return - row.mean_reward) * (e.episode_return - row.mean_reward);
  row.std_reward = std::sqrt(sq / static_cast<double>(episodes.size()));
  row.success = successes / static_cast<double>(episodes.size());
  return row;
}

std::vector<Scored> FromEval(const EvalResult& eval) {
  std::vector<Scored> out;
  for (const auto& t : eval.per_task) {
    for (const auto& e : t.episodes) out.push_back({e.episode_return, e.success.value_or(false)});
  }
  return out;
}

std::vector<Scored> FromMetaTest(const MetaTestResult& result) {
  std::vector<Scored> out;
  for (const auto& e : result.episodes) {
    if (e.evaluation) out.push_back({e.episode_return, e.success.value_or(false)});
  }
  return out;
}

// What one training run cost.
struct RunCost {
  int64_t env_steps = 0;
  double wall_s = 0.0;
};

RunCost CostOf(const fs::path& dir) {
  const RunInfo info = RunInfo::Read(dir);
  std::ifstream in(RunPaths{dir}.summary());
  const nlohmann::json summary = nlohmann::json::parse(in);
  return {summary.at("step").get<int64_t>() * info.tasks.size() * info.config.env.envs_per_task,
          summary.at("wall_s").get<double>()};
}

// Trains (or resumes, or skips when finished) the run of `config`.
RunCost TrainRun(const TrainConfig& config, const std::function<void(const TrainProgress&)>& progress,
                 const StudyCallbacks& callbacks) {
  const fs::path dir = config.experiment.run_dir;
  const RunPaths paths{dir};
  if (fs::exists(paths.summary())) return CostOf(dir);
  std::optional<Trainer> trainer;
  if (fs::exists(paths.config())) {
    const bool has_checkpoint = fs::exists(paths.checkpoints() / "latest");
    trainer.emplace(Trainer::Resume(dir, /*restart=*/!has_checkpoint));
  } else {
    trainer.emplace(Trainer::Create(config));
  }
  TrainCallbacks train_callbacks;
  train_callbacks.on_round = progress;
  train_callbacks.stop_requested = callbacks.stop_requested;
  const TrainSummary summary = trainer->Run(train_callbacks);
  if (!summary.finished) {
    throw StudyStopped("study stopped during '" + dir.string() +
                       "' (checkpointed); run the same command again to resume");
  }
  trainer.reset();  // releases the run lock
  return CostOf(dir);
}

// The run's tasks replaced by `tasks` (evaluation on other tasks).
RunInfo WithTasks(const fs::path& dir, const TaskSet& tasks) {
  RunInfo info = RunInfo::Read(dir);
  info.tasks = tasks;
  return info;
}

nlohmann::json PaperJson(const std::optional<PaperNumbers>& p) {
  if (!p) return nullptr;
  return {{"mean_reward", p->mean_reward}, {"std_reward", p->std_reward}, {"success", p->success}};
}

std::string Num(double v, int digits) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, v);
  return text;
}

// As a user typed it (errors): -3, 0.25, 1e+300.
std::string Short(double v) {
  char text[64];
  std::snprintf(text, sizeof(text), "%g", v);
  return text;
}

}  // namespace

const std::vector<std::string>& StudyMethods() {
  static const std::vector<std::string> methods = {"oracle",    "baseline", "finetune",
                                                   "multitask", "maml",     "pearl", "rl2"};
  return methods;
}

const std::vector<std::string>& PaperMethods() {
  static const std::vector<std::string> methods = {"oracle",    "baseline", "finetune",
                                                   "multitask", "maml",     "pearl"};
  return methods;
}

std::filesystem::path PublishedResultsFile(const StudyOptions& options) {
  return options.config_dir / "published" / "boxworld_study.yaml";
}

std::optional<PaperNumbers> PaperResult(const StudyOptions& options, const std::string& method) {
  const fs::path file = PublishedResultsFile(options);
  if (!fs::exists(file)) return std::nullopt;
  const nlohmann::json table = LoadYamlFile(file);
  if (!table.is_object() || !table.contains(options.task) || !table[options.task].is_object() ||
      !table[options.task].contains(method)) {
    return std::nullopt;
  }
  const std::string where = file.string() + ": " + options.task + "." + method;
  ConfigReader r(table[options.task][method], where);
  PaperNumbers numbers;
  r.Read("mean_reward", numbers.mean_reward);
  r.Read("std_reward", numbers.std_reward);
  r.Read("success", numbers.success);
  r.Finish();
  return numbers;
}

void ValidateStudyOptions(const StudyOptions& o) {
  if (o.task != "simple" && o.task != "complex") {
    throw ConfigError("--task must be simple or complex, got '" + o.task + "'");
  }
  if (o.distribution != "narrow" && o.distribution != "broad") {
    throw ConfigError("--distribution must be narrow or broad, got '" + o.distribution + "'");
  }
  if (!(o.budget > 0.0) || !std::isfinite(o.budget) || o.budget > 1000.0) {
    throw ConfigError("--budget must be a factor in (0, 1000] (1 = the configs' budgets), got " +
                      Short(o.budget));
  }
  for (const auto& m : o.methods) {
    const auto& all = StudyMethods();
    if (std::find(all.begin(), all.end(), m) == all.end()) {
      throw ConfigError("--methods: unknown method '" + m + "'" + SuggestNearest(m, all) +
                        "; the methods are " + JoinNames(all));
    }
  }
  if (o.out_dir.empty()) throw ConfigError("--out must not be empty");
  if (!o.layout.empty() && o.layout != "paper" && o.layout != "anywhere") {
    throw ConfigError("--layout must be paper or anywhere, got '" + o.layout + "'");
  }
}

std::string StudyLayout(const StudyOptions& o) {
  if (!o.layout.empty()) return o.layout;
  return o.task == "complex" ? "paper" : "anywhere";
}

nlohmann::json StudyEnvOptions(const StudyOptions& o) {
  const bool paper = StudyLayout(o) == "paper";
  nlohmann::json options = {{"target_in_obs", true},
                            {"hide_target", o.hide_target},
                            {"agent_start", paper ? "corner" : "anywhere"},
                            {"box_start_gap", paper ? kPaperBoxStartGap : -1.0}};
  if (o.distribution == "broad") {
    // what the paper held fixed varies here: floor 4-8 m, 1-3 boxes of three
    // shapes and sizes (docs/boxworld.md "The study")
    options["floor_size"] = 4.0;
    options["floor_size_max"] = 8.0;
    options["num_boxes"] = 1;
    options["num_boxes_max"] = 3;
    options["box_shapes"] = "box,cylinder,sphere";
    options["box_size"] = 0.1;
    options["box_size_max"] = 0.2;
  }
  return options;
}

EnvSectionConfig StudyTestSection(const StudyOptions& o) {
  EnvSectionConfig env;
  env.id = EnvId(o);
  env.num_tasks = 1;
  env.variations_per_task = kTestLayouts * (kSupportTargets + kQueryTargets);
  env.task_seed = kTestTaskSeed;
  env.options = StudyEnvOptions(o);
  env.options["targets_per_layout"] = kSupportTargets + kQueryTargets;
  env.support_variations = kSupportTargets;
  env.query_variations = kQueryTargets;
  return env;
}

TrainConfig StudyMethodConfig(const StudyOptions& o, const std::string& method) {
  const fs::path file = o.config_dir / ("boxworld_" + method + "_" + o.task + ".yaml");
  if (!fs::exists(file)) {
    throw ConfigError("study: no config '" + file.string() + "' (run from the source tree or " +
                      "pass --configs DIR)");
  }
  TrainConfig c = TrainConfig::Load(file);
  if (!c.env.tasks.empty() || c.env.id != EnvId(o)) {
    throw ConfigError("study: '" + file.string() + "' must train on env.id " + EnvId(o));
  }
  const nlohmann::json study_options = StudyEnvOptions(o);
  for (const auto& [key, value] : study_options.items()) c.env.options[key] = value;
  c.eval_env.reset();  // the study evaluates on its own test tasks
  c.experiment.seed = o.seed;
  c.experiment.run_dir = (o.out_dir / method).string();
  c.experiment.steps_per_task = std::max<int64_t>(
      1, std::llround(static_cast<double>(c.experiment.steps_per_task) * o.budget));
  c.experiment.eval_every = 0;  // the trainer's own evaluation only at the end
  c.experiment.checkpoint_every = std::max<int64_t>(1, c.experiment.steps_per_task / 4);
  c.Validate();
  return c;
}

std::vector<StudyRow> RunBoxWorldStudy(const StudyOptions& options,
                                       const StudyCallbacks& callbacks) {
  ValidateStudyOptions(options);
  std::vector<std::string> methods;
  for (const auto& m : StudyMethods()) {
    if (options.methods.empty() ? m != "rl2"
                                : std::find(options.methods.begin(), options.methods.end(), m) !=
                                      options.methods.end()) {
      methods.push_back(m);
    }
  }
  // every config is read and checked before anything trains
  std::map<std::string, TrainConfig> configs;
  for (const auto& m : methods) configs.emplace(m, StudyMethodConfig(options, m));
  if (configs.count("finetune") && !configs.count("baseline")) {
    configs.emplace("baseline", StudyMethodConfig(options, "baseline"));
  }
  const TaskSet test_tasks = ResolveTasks(StudyTestSection(options), DefaultRegistry());
  const TaskSet query_tasks = test_tasks.QueryVariations();
  const int64_t test_episodes = kTestLayouts * kQueryTargets;
  const uint64_t eval_seed = MixSeed(options.seed, kStudyEvalStream);
  fs::create_directories(options.out_dir);

  std::vector<StudyRow> rows;
  for (size_t i = 0; i < methods.size(); ++i) {
    const std::string& method = methods[i];
    const fs::path result_file = options.out_dir / method / "result.json";
    if (fs::exists(result_file)) {
      std::ifstream in(result_file);
      StudyRow row = StudyRow::FromJson(nlohmann::json::parse(in));
      row.paper = PaperResult(options, method);
      if (callbacks.on_row) callbacks.on_row(row, true);
      rows.push_back(row);
      continue;
    }
    const auto start = Clock::now();
    StudyProgress progress{method, static_cast<int64_t>(i), static_cast<int64_t>(methods.size()),
                           "train", {}};
    auto report = [&](const std::string& phase) {
      return [&, phase](const TrainProgress& p) {
        progress.phase = phase;
        progress.train = p;
        if (callbacks.on_progress) callbacks.on_progress(progress);
      };
    };
    auto announce = [&](const std::string& phase) {
      if (callbacks.stop_requested && callbacks.stop_requested()) {
        throw StudyStopped("study stopped before the " + phase + " phase of '" + method +
                           "'; run the same command again to resume (finished methods are kept)");
      }
      progress.phase = phase;
      progress.train = {};
      if (callbacks.on_progress) callbacks.on_progress(progress);
    };
    RunCost cost;
    std::vector<Scored> scored;
    const std::string method_for_run = method == "finetune" ? "baseline" : method;
    if (method == "finetune") {
      // pre-training: the baseline's run (trained here if not yet)
      const RunCost pre = TrainRun(configs.at("baseline"), report("pre-train (baseline run)"),
                                   callbacks);
      const fs::path pretrained = LatestCheckpoint(configs.at("baseline").experiment.run_dir);
      cost.env_steps += pre.env_steps;
      for (int64_t k = 0; k < kFinetuneTasks; ++k) {
        TrainConfig c = configs.at("finetune");
        const fs::path dir = options.out_dir / "finetune" / ("task_" + std::to_string(k));
        c.experiment.run_dir = dir.string();
        c.experiment.init_from = fs::absolute(pretrained).string();
        c.env.num_tasks = 1;
        c.env.variations_per_task = 0;
        c.env.task_states = nlohmann::json::array(
            {test_tasks.tasks[0].variations[test_tasks.SupportVariation(k, 0)].ToJson()});
        const RunCost run = TrainRun(
            c, report("fine-tune on test task " + std::to_string(k + 1) + "/" +
                      std::to_string(kFinetuneTasks)),
            callbacks);
        cost.env_steps += run.env_steps;
        announce("evaluate");
        // scored on the layout's query targets
        TaskSet layout_queries = query_tasks;
        auto& variations = layout_queries.tasks[0].variations;
        variations = {variations.begin() + k * kQueryTargets,
                      variations.begin() + (k + 1) * kQueryTargets};
        const auto eval = EvaluateCheckpoint(WithTasks(dir, layout_queries), LatestCheckpoint(dir),
                                             kQueryTargets, eval_seed);
        for (const auto& s : FromEval(eval)) scored.push_back(s);
      }
    } else {
      const TrainConfig& c = configs.at(method_for_run);
      cost = TrainRun(c, report("train"), callbacks);
      const fs::path dir = c.experiment.run_dir;
      const fs::path checkpoint = LatestCheckpoint(dir);
      announce("evaluate");
      if (method == "oracle") {
        scored = FromEval(EvaluateCheckpoint(RunInfo::Read(dir), checkpoint, test_episodes,
                                             eval_seed));
      } else if (IsMetaMethod(method)) {
        RunInfo info = RunInfo::Read(dir);
        info.eval_tasks = test_tasks;
        // one trial per test layout: exploration on its support targets, one evaluation
        // episode on each of its query targets
        info.config.meta_test.evaluation_episodes = kQueryTargets;
        scored = FromMetaTest(MetaTestCheckpointEpisodes(info, checkpoint, kTestLayouts,
                                                         eval_seed));
      } else {  // baseline, multitask: the test layouts' query targets
        scored = FromEval(EvaluateCheckpoint(WithTasks(dir, query_tasks), checkpoint,
                                             test_episodes, eval_seed));
      }
    }
    StudyRow row = RowFrom(method, scored);
    row.train_env_steps = cost.env_steps;
    row.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    fs::create_directories(result_file.parent_path());
    AtomicWriteFile(result_file, row.ToJson().dump(2) + "\n");
    row.paper = PaperResult(options, method);
    if (callbacks.on_row) callbacks.on_row(row, false);
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json StudyRow::ToJson() const {
  return {{"method", method},           {"episodes", episodes},
          {"mean_reward", mean_reward}, {"std_reward", std_reward},
          {"success", success},         {"train_env_steps", train_env_steps},
          {"wall_s", wall_s},           {"paper", PaperJson(paper)}};
}

StudyRow StudyRow::FromJson(const nlohmann::json& json) {
  try {
    StudyRow row;
    row.method = json.at("method").get<std::string>();
    row.episodes = json.at("episodes").get<int64_t>();
    row.mean_reward = json.at("mean_reward").get<double>();
    row.std_reward = json.at("std_reward").get<double>();
    row.success = json.at("success").get<double>();
    row.train_env_steps = json.at("train_env_steps").get<int64_t>();
    row.wall_s = json.at("wall_s").get<double>();
    return row;
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("malformed study result: ") + e.what());
  }
}

nlohmann::json StudyTableJson(const std::vector<StudyRow>& rows, const StudyOptions& o) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& r : rows) list.push_back(r.ToJson());
  return {{"task", o.task},
          {"distribution", o.distribution},
          {"hide_target", o.hide_target},
          {"budget", o.budget},
          {"seed", o.seed},
          {"layout", StudyLayout(o)},
          {"test_layouts", kTestLayouts},
          {"support_targets", kSupportTargets},
          {"query_targets", kQueryTargets},
          {"rows", list}};
}

std::string StudyTableCsv(const std::vector<StudyRow>& rows) {
  std::ostringstream out;
  out << "method,episodes,mean_reward,std_reward,success_pct,paper_mean_reward,"
         "paper_std_reward,paper_success_pct,train_env_steps,wall_s\n";
  for (const auto& r : rows) {
    out << r.method << ',' << r.episodes << ',' << Num(r.mean_reward, 4) << ','
        << Num(r.std_reward, 4) << ',' << Num(100 * r.success, 2) << ',';
    if (r.paper) {
      out << Num(r.paper->mean_reward, 4) << ',' << Num(r.paper->std_reward, 4) << ','
          << Num(100 * r.paper->success, 2);
    } else {
      out << ",,";
    }
    out << ',' << r.train_env_steps << ',' << Num(r.wall_s, 1) << '\n';
  }
  return out.str();
}

std::string StudyTableMarkdown(const std::vector<StudyRow>& rows, const StudyOptions& o) {
  std::ostringstream out;
  out << "Box world study: " << o.task << " task, " << o.distribution << " distribution, target "
      << (o.hide_target ? "hidden" : "observed") << ", budget x" << Num(o.budget, 3) << ", seed "
      << o.seed << ", "
      << (StudyLayout(o) == "paper" ? "the paper's layout (agent in a corner, box touching it)"
                                    : "agent and boxes start anywhere")
      << "; " << kTestLayouts << " test layouts x " << kSupportTargets << " support + "
      << kQueryTargets << " query targets (scored on the query targets).\n\n";
  out << "| method | mean reward | std | success | paper mean | paper std | paper success | "
         "training env steps | wall |\n";
  out << "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : rows) {
    out << "| " << r.method << " | " << Num(r.mean_reward, 2) << " | " << Num(r.std_reward, 2)
        << " | " << Num(100 * r.success, 1) << " % | ";
    if (r.paper) {
      out << Num(r.paper->mean_reward, 2) << " | " << Num(r.paper->std_reward, 2) << " | "
          << Num(100 * r.paper->success, 1) << " % | ";
    } else {
      out << "- | - | - | ";
    }
    out << r.train_env_steps << " | " << Num(r.wall_s, 0) << " s |\n";
  }
  return out.str();
}

void WriteStudyTables(const std::vector<StudyRow>& rows, const StudyOptions& o) {
  fs::create_directories(o.out_dir);
  AtomicWriteFile(o.out_dir / "table.json", StudyTableJson(rows, o).dump(2) + "\n");
  AtomicWriteFile(o.out_dir / "table.csv", StudyTableCsv(rows));
  AtomicWriteFile(o.out_dir / "table.md", StudyTableMarkdown(rows, o));
}

}  // namespace manyworlds::experiments
