#include "manyworlds/experiments/trainer.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/core/atomic_file.h"
#include "manyworlds/config/yaml.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/executor.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"
#include "manyworlds/experiments/algorithm.h"
#include "manyworlds/experiments/algorithms.h"
#include "manyworlds/experiments/checkpoint_integrity.h"
#include "manyworlds/experiments/meta_test_protocol.h"
#include "manyworlds/experiments/collector.h"
#include "manyworlds/experiments/run_lock.h"
#include "manyworlds/experiments/run_log.h"
#include "manyworlds/nn/threads.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The stream of experiment.seed that seeds torch's default generator (the
// algorithms derive their own streams).
constexpr uint64_t kTorchStream = 0x746f726368;  // "torch"

constexpr char kCheckpointFormat[] = "manyworlds-train-checkpoint";
constexpr int kCheckpointVersion = 1;
constexpr char kLatestFile[] = "latest";


// True when a multiple of `every` lies in (prev, step].
bool Due(int64_t prev, int64_t step, int64_t every) {
  return every > 0 && step / every != prev / every;
}

std::string CheckpointName(int64_t step) {
  char name[32];
  std::snprintf(name, sizeof(name), "step_%012lld", static_cast<long long>(step));
  return name;
}

// Makes a written file (or a directory's entries) durable; Error naming the
// path if the kernel reports a write-back failure (EIO, ENOSPC).
void FsyncPath(const fs::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) throw Error("cannot open '" + path.string() + "' to sync it: " + std::strerror(errno));
  const int synced = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  // directories on some file systems refuse fsync (EINVAL): nothing to report there
  if (synced != 0 && !(directory && error == EINVAL)) {
    throw Error("cannot sync '" + path.string() + "': " + std::strerror(error));
  }
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

nlohmann::json OptionalEval(const std::optional<EvalResult>& eval) {
  return eval ? eval->ToJson() : nlohmann::json(nullptr);
}

std::optional<EvalResult> EvalFromJson(const nlohmann::json& json) {
  if (json.is_null()) return std::nullopt;
  EvalResult r;
  r.step = json.at("step").get<int64_t>();
  r.episodes_per_task = json.at("episodes_per_task").get<int64_t>();
  if (!json.at("mean_success").is_null()) r.mean_success = json["mean_success"].get<double>();
  r.mean_return = json.at("mean_return").get<double>();
  r.wall_s = json.at("wall_s").get<double>();
  for (const auto& [name, t] : json.at("per_task").items()) {
    TaskEvalResult task;
    task.task = name;
    if (!t.at("success").is_null()) task.success = t["success"].get<double>();
    task.mean_return = t.at("return").get<double>();
    task.mean_length = t.at("length").get<double>();
    r.per_task.push_back(std::move(task));
  }
  return r;
}

// "checkpoint 'D' was written with B BLAS thread(s) and T torch thread(s);
// this process has ..." where the counts in a checkpoint's thread record
// differ from this process's; nothing when they agree.
std::optional<std::string> ThreadCountMismatch(const fs::path& dir, const nlohmann::json& saved,
                                               const nn::ThreadInfo& now) {
  const int64_t torch_then = saved.value("torch_intra_op", int64_t{-1});
  const int64_t blas_then = saved.value("blas_threads", int64_t{-1});
  if (torch_then == now.torch_intra_op && blas_then == now.blas_threads) return std::nullopt;
  return "checkpoint '" + dir.string() + "' was written with " + std::to_string(blas_then) +
         " BLAS thread(s) and " + std::to_string(torch_then) + " torch thread(s); this process has " +
         std::to_string(now.blas_threads) + " and " + std::to_string(now.torch_intra_op);
}

}  // namespace

nlohmann::json TrainSummary::ToJson() const {
  return {{"finished", finished},
          {"step", step},
          {"updates", updates},
          {"wall_s", wall_s},
          {"env_steps_per_s", env_steps_per_s},
          {"updates_per_s", updates_per_s},
          {"final_eval", OptionalEval(final_eval)},
          {"final_meta_test", final_meta_test ? *final_meta_test : nlohmann::json(nullptr)},
          {"final_meta_train", final_meta_train ? *final_meta_train : nlohmann::json(nullptr)}};
}

fs::path LatestCheckpoint(const fs::path& run_dir) { return ChooseCheckpoint(run_dir).dir; }

std::optional<std::string> EvaluationThreadWarning(const fs::path& checkpoint) {
  try {
    const nlohmann::json state = nlohmann::json::parse(ReadText(checkpoint / "state.json"));
    if (!state.is_object() || !state.contains("threads") || !state["threads"].is_object()) {
      return std::nullopt;  // older checkpoints
    }
    const nlohmann::json& saved = state["threads"];
    const auto mismatch = ThreadCountMismatch(checkpoint, saved, nn::CurrentThreads());
    if (!mismatch) return std::nullopt;
    return *mismatch + ": the numbers may differ from the run's own evaluations in the "
           "rounding, and sampled episodes then diverge; OPENBLAS_NUM_THREADS=" +
           std::to_string(saved.value("blas_threads", int64_t{-1})) + " reproduces them";
  } catch (const std::exception&) {
    return std::nullopt;  // a damaged checkpoint is the evaluation's error to report
  }
}

RunInfo RunInfo::Read(const fs::path& run_dir) {
  const RunPaths paths{run_dir};
  if (!fs::is_directory(run_dir)) {
    throw ConfigError("run directory '" + run_dir.string() + "' does not exist");
  }
  if (!fs::exists(paths.config()) || !fs::exists(paths.tasks())) {
    throw ConfigError("'" + run_dir.string() +
                      "' is not a run directory (no config.yaml and tasks.json)");
  }
  RunInfo info;
  info.config = TrainConfig::Load(paths.config());
  info.config.Validate();
  const auto tasks = nlohmann::json::parse(ReadText(paths.tasks()), nullptr, false);
  if (tasks.is_discarded()) throw Error(paths.tasks().string() + ": not valid JSON");
  try {
    info.tasks = TaskSet::FromJson(tasks);
  } catch (const Error& e) {
    throw Error(paths.tasks().string() + ": " + e.what());
  }
  if (info.config.eval_env) {
    const auto eval_tasks = nlohmann::json::parse(ReadText(paths.eval_tasks()), nullptr, false);
    if (eval_tasks.is_discarded()) throw Error(paths.eval_tasks().string() + ": not valid JSON");
    try {
      info.eval_tasks = TaskSet::FromJson(eval_tasks);
    } catch (const Error& e) {
      throw Error(paths.eval_tasks().string() + ": " + e.what());
    }
  }
  return info;
}

namespace {

// The step a checkpoint was taken at; Error naming the file if unreadable.
int64_t CheckpointStep(const fs::path& checkpoint) {
  const auto state = nlohmann::json::parse(ReadText(checkpoint / "state.json"), nullptr, false);
  if (state.is_object() && state.contains("step") && state["step"].is_number_integer() &&
      state["step"].get<int64_t>() >= 0) {
    return state["step"].get<int64_t>();
  }
  throw Error("checkpoint '" + checkpoint.string() + "': state.json has no valid step");
}

// Removes what a killed writer left behind: hidden `.NAME.tmp.XXXXXX` files
// (AtomicWriteFile) in the run and checkpoint directories and partial
// `.tmp_step_*` checkpoints. Only under the run's lock: no writer is alive.
void RemoveStaleTemporaries(const fs::path& run_dir) {
  for (const fs::path& dir : {run_dir, RunPaths{run_dir}.checkpoints()}) {
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(dir, ec))) continue;
    std::vector<fs::path> stale;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      const bool temp_file = name.size() > 1 && name[0] == '.' &&
                             name.find(".tmp.") != std::string::npos &&
                             entry.is_regular_file(ec);
      const bool temp_checkpoint = name.rfind(".tmp_step_", 0) == 0;
      if (temp_file || temp_checkpoint) stale.push_back(entry.path());
    }
    for (const fs::path& p : stale) fs::remove_all(p, ec);
  }
}

// Held-out tasks must present the spaces the policy was trained on.
void CheckEvalTasks(const TaskSet& eval_tasks, const EnvFacts& train, const Registry& registry) {
  const EnvFacts eval = InspectEnvs(eval_tasks, registry);
  if (eval.obs_dim != train.obs_dim || eval.action_dim != train.action_dim ||
      eval.num_actions != train.num_actions) {
    throw ConfigError("eval_env: its tasks' observation or action spaces differ from env's (obs " +
                      std::to_string(eval.obs_dim) + " vs " + std::to_string(train.obs_dim) +
                      ", action " + std::to_string(eval.action_dim) + " vs " +
                      std::to_string(train.action_dim) + ")");
  }
}

}  // namespace

namespace {

MetaTestResult RunMetaTestOn(const RunInfo& run, const fs::path& checkpoint,
                             const MetaTestConfig& config, uint64_t seed, bool on_training_tasks) {
  if (!run.eval_tasks) {
    throw ConfigError(std::string(on_training_tasks ? "meta-train" : "meta-test") +
                      " needs held-out tasks, and this run has none: train with an "
                      "eval_env section (e.g. eval_env: {options: {split: test}} for ML1/ML10, "
                      "or eval_env: {task_seed: 1} for a sampled task distribution)");
  }
  const Registry& registry = DefaultRegistry();
  const EnvFacts facts = InspectEnvs(run.tasks, registry);
  CheckEvalTasks(*run.eval_tasks, facts, registry);
  std::unique_ptr<Algorithm> algorithm = BuildAlgorithm(run.config, run.tasks, facts);
  algorithm->LoadPolicy(checkpoint);
  MetaTestProtocol protocol(on_training_tasks ? run.tasks : *run.eval_tasks, registry, config,
                            seed, run.config.experiment.num_threads);
  MetaTestResult result = protocol.RunMetaTest(algorithm->actor());
  result.step = CheckpointStep(checkpoint);
  return result;
}

}  // namespace

nlohmann::json MetaTestCheckpoint(const RunInfo& run, const fs::path& checkpoint,
                                  std::optional<uint64_t> seed) {
  return RunMetaTestOn(run, checkpoint, run.config.meta_test,
                       seed ? *seed : MixSeed(run.config.experiment.seed, kMetaTestSeedStream),
                       /*on_training_tasks=*/false)
      .ToJson();
}

nlohmann::json MetaTrainCheckpoint(const RunInfo& run, const fs::path& checkpoint,
                                   std::optional<uint64_t> seed) {
  return RunMetaTestOn(run, checkpoint, run.config.meta_test,
                       seed ? *seed : MixSeed(run.config.experiment.seed, kMetaTrainSeedStream),
                       /*on_training_tasks=*/true)
      .ToJson();
}

MetaTestResult MetaTestCheckpointEpisodes(const RunInfo& run, const fs::path& checkpoint,
                                          int64_t trials, uint64_t seed) {
  MetaTestConfig config = run.config.meta_test;
  config.trials_per_task = trials;
  return RunMetaTestOn(run, checkpoint, config, seed, /*on_training_tasks=*/false);
}

std::unique_ptr<Algorithm> BuildAlgorithm(const TrainConfig& config, const TaskSet& tasks,
                                          const EnvFacts& facts) {
  CheckAlgorithmEnvs(config.agent, facts, tasks);
  AlgorithmSetup setup{config, facts, tasks, tasks.size(),
                       tasks.size() * config.env.envs_per_task, facts.episode_length};
  return MakeAlgorithm(setup);
}

EvalResult EvaluateCheckpoint(const RunInfo& run, const fs::path& checkpoint, int64_t episodes,
                              std::optional<uint64_t> seed) {
  const Registry& registry = DefaultRegistry();
  const EnvFacts facts = InspectEnvs(run.tasks, registry);
  std::unique_ptr<Algorithm> algorithm = BuildAlgorithm(run.config, run.tasks, facts);
  algorithm->LoadPolicy(checkpoint);
  Evaluator evaluator(run.tasks, registry, episodes,
                      seed ? *seed : MixSeed(run.config.experiment.seed, kEvalSeedStream),
                      run.config.experiment.num_threads);
  EvalResult result = evaluator.Run(algorithm->actor());
  result.step = CheckpointStep(checkpoint);
  return result;
}

struct Trainer::Impl {
  std::unique_ptr<RunLock> lock;  // held while this trainer may write the run
  RunPaths paths;
  TrainConfig config;
  TaskSet tasks;
  EnvFacts facts;
  const Registry& registry = DefaultRegistry();

  int64_t num_tasks = 0;
  int64_t num_envs = 0;
  int64_t round_length = 0;
  int64_t rounds_per_iteration = 1;
  int64_t total_steps = 0;

  std::unique_ptr<Collector> collector;
  std::unique_ptr<Algorithm> algorithm;
  std::unique_ptr<Evaluator> evaluator;
  std::optional<TaskSet> eval_tasks;
  std::unique_ptr<MetaTestProtocol> meta_test;
  std::unique_ptr<MetaTestProtocol> meta_train;  // the same protocol on the training tasks
  std::unique_ptr<RunLog> metrics_log;
  std::unique_ptr<RunLog> eval_log;
  std::unique_ptr<RunLog> meta_test_log;
  std::unique_ptr<RunLog> meta_train_log;
  std::optional<nlohmann::json> last_meta_test;   // this session's
  std::optional<nlohmann::json> last_meta_train;  // this session's
  std::vector<std::string> warnings;              // found by Resume

  // counters (checkpointed)
  int64_t step = 0;
  int64_t round = 0;
  double wall_before = 0.0;  // wall time of earlier sessions
  std::optional<EvalResult> last_eval;

  void CheckThreads(const fs::path& dir, const nlohmann::json& state);
  void Setup(const TrainConfig& c, TaskSet t, std::optional<TaskSet> held_out,
             const fs::path& run_dir);
  EvalResult Evaluate();
  fs::path SaveCheckpoint();
  void LoadCheckpoint(const fs::path& dir);
  TrainSummary Run(const TrainCallbacks& callbacks);
};

void Trainer::Impl::Setup(const TrainConfig& c, TaskSet t, std::optional<TaskSet> held_out,
                          const fs::path& run_dir) {
  config = c;
  tasks = std::move(t);
  eval_tasks = std::move(held_out);
  paths = RunPaths{run_dir};
  facts = InspectEnvs(tasks, registry);
  num_tasks = tasks.size();
  num_envs = num_tasks * config.env.envs_per_task;
  round_length = facts.episode_length;

  torch::manual_seed(MixSeed(config.experiment.seed, kTorchStream));
  algorithm = BuildAlgorithm(config, tasks, facts);
  rounds_per_iteration = algorithm->rounds_per_iteration();
  const int64_t iteration_steps = rounds_per_iteration * round_length;
  const int64_t iterations =
      (config.experiment.steps_per_task + iteration_steps - 1) / iteration_steps;
  total_steps = iterations * iteration_steps;
  collector = std::make_unique<Collector>(tasks, registry, facts, config.env.envs_per_task,
                                          config.experiment.num_threads);
  evaluator = std::make_unique<Evaluator>(tasks, registry, config.experiment.eval_episodes,
                                          MixSeed(config.experiment.seed, kEvalSeedStream),
                                          config.experiment.num_threads);
  if (eval_tasks) {
    CheckEvalTasks(*eval_tasks, facts, registry);
    meta_test = std::make_unique<MetaTestProtocol>(
        *eval_tasks, registry, config.meta_test,
        MixSeed(config.experiment.seed, kMetaTestSeedStream), config.experiment.num_threads);
    meta_train = std::make_unique<MetaTestProtocol>(
        tasks, registry, config.meta_test, MixSeed(config.experiment.seed, kMetaTrainSeedStream),
        config.experiment.num_threads);
  }
}

EvalResult Trainer::Impl::Evaluate() {
  EvalResult result = evaluator->Run(algorithm->actor());
  result.step = step;
  if (meta_test) {
    MetaTestResult meta = meta_test->RunMetaTest(algorithm->actor());
    meta.step = step;
    last_meta_test = meta.ToJson();
    meta_test_log->Append(*last_meta_test);
    MetaTestResult train = meta_train->RunMetaTest(algorithm->actor());
    train.step = step;
    last_meta_train = train.ToJson();
    meta_train_log->Append(*last_meta_train);
  }
  return result;
}

fs::path Trainer::Impl::SaveCheckpoint() {
  const fs::path dir = paths.checkpoints();
  fs::create_directories(dir);
  const std::string name = CheckpointName(step);
  const fs::path final_dir = dir / name;
  const fs::path tmp = dir / (".tmp_" + name);
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  // a failed write (full disk, I/O error) removes the partial checkpoint and
  // leaves the previous one as the newest: the run resumes from there
  struct RemoveUnlessDone {
    const fs::path& dir;
    bool done = false;
    ~RemoveUnlessDone() {
      std::error_code ignored;
      if (!done) fs::remove_all(dir, ignored);
    }
  } cleanup{tmp};
  nlohmann::json state = {
      {"format", kCheckpointFormat},
      {"version", kCheckpointVersion},
      {"algo", config.agent.algo()},
      {"step", step},
      {"round", round},
      {"updates", algorithm->updates()},
      {"wall_s", wall_before},
      {"num_tasks", num_tasks},
      {"num_envs", num_envs},
      {"obs_dim", facts.obs_dim},
      {"action_dim", facts.action_dim},
      {"last_eval", OptionalEval(last_eval)},
  };
  // the reduction order of products depends on these: resume checks them
  const nn::ThreadInfo threads = nn::CurrentThreads();
  state["threads"] = {{"torch_intra_op", threads.torch_intra_op},
                      {"blas_threads", threads.blas_threads},
                      {"blas_core", threads.blas_core}};
  algorithm->Save(tmp, state);
  SealCheckpointState(tmp, paths.dir, state);
  AtomicWriteFile(tmp / "state.json", state.dump(2) + "\n");
  for (const auto& entry : fs::directory_iterator(tmp)) FsyncPath(entry.path(), false);
  FsyncPath(tmp, true);
  fs::remove_all(final_dir);
  fs::rename(tmp, final_dir);
  cleanup.done = true;
  FsyncPath(dir, true);
  AtomicWriteFile(dir / kLatestFile, name + "\n");

  // prune older checkpoints beyond keep_checkpoints (never the newest)
  const int64_t keep = config.experiment.keep_checkpoints;
  if (keep > 0) {
    std::vector<fs::path> found;
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string n = entry.path().filename().string();
      if (entry.is_directory() && n.rfind("step_", 0) == 0) found.push_back(entry.path());
    }
    std::sort(found.begin(), found.end());
    for (size_t i = 0; i + keep < found.size(); ++i) {
      if (found[i] != final_dir) fs::remove_all(found[i]);
    }
  }
  return final_dir;
}

// A product's rounding depends on how many threads share it (measured: the
// same seed gave -85.28154 with one OpenBLAS thread and -85.28158 with two),
// so a run resumes exactly only with the thread counts it was trained with.
void Trainer::Impl::CheckThreads(const fs::path& dir, const nlohmann::json& state) {
  if (!state.contains("threads") || !state["threads"].is_object()) return;  // older checkpoints
  const nlohmann::json& saved = state["threads"];
  const nn::ThreadInfo now = nn::CurrentThreads();
  if (const auto mismatch = ThreadCountMismatch(dir, saved, now)) {
    throw ConfigError(*mismatch + ", so the resumed numbers would not match an uninterrupted run; "
                      "resume with OPENBLAS_NUM_THREADS=" +
                      std::to_string(saved.value("blas_threads", int64_t{-1})) +
                      " (and the run's own config)");
  }
  const std::string core_then = saved.value("blas_core", std::string("unknown"));
  if (core_then != now.blas_core) {
    warnings.push_back("checkpoint '" + dir.string() + "' was written with OpenBLAS kernels '" +
                       core_then + "', this machine uses '" + now.blas_core +
                       "': the numbers will differ from an uninterrupted run in the last digits");
  }
}

void Trainer::Impl::LoadCheckpoint(const fs::path& dir) {
  nlohmann::json state;
  try {
    state = nlohmann::json::parse(ReadText(dir / "state.json"));
  } catch (const std::exception& e) {
    const std::string what = e.what();
    throw Error("checkpoint '" + dir.string() + "': unreadable state.json: " +
                what.substr(0, what.find('\n')));
  }
  auto expect = [&](const char* key, int64_t want) {
    if (!state.contains(key) || !state[key].is_number_integer() ||
        state[key].get<int64_t>() != want) {
      throw Error("checkpoint '" + dir.string() + "' does not match this run: " + key + " is " +
                  (state.contains(key) ? state[key].dump() : "missing") + ", expected " +
                  std::to_string(want));
    }
  };
  if (state.value("format", "") != kCheckpointFormat) {
    throw Error("checkpoint '" + dir.string() + "': state.json is not a training checkpoint");
  }
  // checkpoints written before the algorithm registry are SAC's
  const std::string algo = state.value("algo", std::string("sac"));
  if (algo != config.agent.algo()) {
    throw Error("checkpoint '" + dir.string() + "' is of algorithm '" + algo +
                "', this run is '" + config.agent.algo() + "'");
  }
  expect("version", kCheckpointVersion);
  expect("num_tasks", num_tasks);
  expect("num_envs", num_envs);
  expect("obs_dim", facts.obs_dim);
  expect("action_dim", facts.action_dim);
  int64_t new_step = 0, new_round = 0;
  double new_wall = 0.0;
  std::optional<EvalResult> new_eval;
  try {
    new_step = state.at("step").get<int64_t>();
    new_round = state.at("round").get<int64_t>();
    state.at("updates").get<int64_t>();
    new_wall = state.at("wall_s").get<double>();
    new_eval = EvalFromJson(state.at("last_eval"));
  } catch (const std::exception& e) {
    const std::string what = e.what();
    throw Error("checkpoint '" + dir.string() + "': malformed state.json (" +
                what.substr(0, what.find('\n')) + ")");
  }
  if (new_step < 0 || new_step > total_steps || new_step != new_round * round_length ||
      new_round % rounds_per_iteration != 0) {
    throw Error("checkpoint '" + dir.string() + "': step " + std::to_string(new_step) +
                " is not an iteration boundary of this run");
  }
  CheckThreads(dir, state);
  algorithm->Load(dir, state);
  step = new_step;
  round = new_round;
  wall_before = new_wall;
  last_eval = std::move(new_eval);
}

TrainSummary Trainer::Impl::Run(const TrainCallbacks& callbacks) {
  const auto session_start = Clock::now();
  const int64_t session_start_step = step;
  const int64_t session_start_updates = algorithm->updates();
  const int64_t iteration_steps = rounds_per_iteration * round_length;

  auto progress = [&]() {
    TrainProgress p;
    p.step = step;
    p.total_steps = total_steps;
    p.updates = algorithm->updates();
    const double session = Seconds(Clock::now() - session_start);
    p.elapsed_s = wall_before + session;
    if (session > 0) {
      p.env_steps_per_s = static_cast<double>((step - session_start_step) * num_envs) / session;
      p.updates_per_s = static_cast<double>(p.updates - session_start_updates) / session;
    }
    p.last_eval = last_eval;
    return p;
  };

  bool stopped = false;
  while (step < total_steps && !stopped) {
    const auto iteration_start = Clock::now();
    const int64_t start_updates = algorithm->updates();
    nlohmann::json row = algorithm->TrainIteration(*collector, round, step);
    step += iteration_steps;
    round += rounds_per_iteration;
    const double wall = Seconds(Clock::now() - iteration_start);
    row["step"] = step;
    row["round"] = round;
    row["env_steps"] = step * num_envs;
    row["updates"] = algorithm->updates();
    row["wall_s"] = wall_before + Seconds(Clock::now() - session_start);
    row["env_steps_per_s"] = static_cast<double>(iteration_steps * num_envs) / wall;
    row["updates_per_s"] = static_cast<double>(algorithm->updates() - start_updates) / wall;
    metrics_log->Append(row);

    const int64_t prev = step - iteration_steps;
    const bool last = step >= total_steps;
    if (last || Due(prev, step, config.experiment.eval_every)) {
      last_eval = Evaluate();
      eval_log->Append(last_eval->ToJson());
      if (callbacks.on_eval) callbacks.on_eval(*last_eval);
    }
    const bool stop_now = callbacks.stop_requested && callbacks.stop_requested();
    if (last || stop_now || Due(prev, step, config.experiment.checkpoint_every)) {
      // wall time so far, so that a resumed run keeps counting
      const double before = wall_before;
      wall_before += Seconds(Clock::now() - session_start);
      const fs::path saved = SaveCheckpoint();
      wall_before = before;
      if (callbacks.on_checkpoint) callbacks.on_checkpoint(saved);
      if (callbacks.stop_after_step && step >= *callbacks.stop_after_step) stopped = true;
      if (stop_now) stopped = true;
    }
    if (callbacks.on_round) callbacks.on_round(progress());
  }

  const TrainProgress p = progress();
  TrainSummary summary;
  summary.finished = step >= total_steps;
  summary.step = step;
  summary.updates = p.updates;
  summary.wall_s = p.elapsed_s;
  summary.env_steps_per_s = p.env_steps_per_s;
  summary.updates_per_s = p.updates_per_s;
  summary.final_eval = last_eval;
  summary.final_meta_test = last_meta_test;
  summary.final_meta_train = last_meta_train;
  if (summary.finished) {
    nlohmann::json json = summary.ToJson();
    json["run_dir"] = paths.dir.string();
    json["algo"] = config.agent.algo();
    json["num_tasks"] = num_tasks;
    json["num_envs"] = num_envs;
    json["total_env_steps"] = step * num_envs;
    AtomicWriteFile(paths.summary(), json.dump(2) + "\n");
  }
  return summary;
}

Trainer::Trainer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Trainer::Trainer(Trainer&&) noexcept = default;
Trainer& Trainer::operator=(Trainer&&) noexcept = default;
Trainer::~Trainer() = default;

Trainer Trainer::Create(const TrainConfig& config) {
  config.Validate();
  const fs::path run_dir = config.experiment.run_dir;
  const RunPaths paths{run_dir};
  auto refuse_existing = [&] {
    // an empty checkpoints/ without config.yaml is a creation cut short
    std::error_code ec;
    const bool empty_checkpoints = fs::is_directory(paths.checkpoints(), ec) &&
                                   fs::is_empty(paths.checkpoints(), ec) && !ec;
    if (fs::exists(paths.config()) ||
        (fs::exists(fs::symlink_status(paths.checkpoints())) && !empty_checkpoints)) {
      throw ConfigError("run directory '" + run_dir.string() +
                        "' already holds a run; continue it with `manyworlds train --resume " +
                        run_dir.string() + "` or choose another experiment.run_dir");
    }
  };
  refuse_existing();
  TaskSet tasks = ResolveTasks(config.env, DefaultRegistry());
  std::optional<TaskSet> held_out;
  if (config.eval_env) {
    try {
      held_out = ResolveTasks(*config.eval_env, DefaultRegistry());
    } catch (const ConfigError& e) {
      throw ConfigError(std::string("eval_env: ") + e.what());
    }
  }
  auto impl = std::make_unique<Impl>();
  impl->Setup(config, std::move(tasks), std::move(held_out), run_dir);
  if (!config.experiment.init_from.empty()) {
    // fine-tuning: the learner starts from another run's checkpoint (a
    // resumed run reads its own checkpoints instead)
    const fs::path from = config.experiment.init_from;
    if (!fs::exists(from / "learner.pt")) {
      throw ConfigError("experiment.init_from: '" + from.string() +
                        "' is not a checkpoint directory (no learner.pt)");
    }
    try {
      impl->algorithm->LoadPolicy(from);
    } catch (const std::exception& e) {
      throw ConfigError("experiment.init_from: cannot start from '" + from.string() +
                        "' (same algorithm and network sizes needed): " + e.what());
    }
  }
  // nothing is created before the config has proved runnable
  std::error_code ec;
  fs::create_directories(run_dir, ec);
  if (ec) {
    throw Error("cannot create run directory '" + run_dir.string() + "': " + ec.message());
  }
  // checked again under the lock: of two processes started together, one
  // writes the run and the other is refused
  impl->lock = std::make_unique<RunLock>(run_dir);
  refuse_existing();
  // config.yaml last: a directory is a run once it has one, so a kill
  // before it leaves a directory that `train` may simply start again. An
  // empty checkpoints/ marks a run that has not reached its first checkpoint,
  // which `train --resume` starts again from step 0 (nothing is lost).
  if (impl->eval_tasks) {
    AtomicWriteFile(paths.eval_tasks(), impl->eval_tasks->ToJson().dump(2) + "\n");
  }
  AtomicWriteFile(paths.tasks(), impl->tasks.ToJson().dump(2) + "\n");
  fs::create_directories(paths.checkpoints(), ec);
  if (ec) {
    throw Error("cannot create '" + paths.checkpoints().string() + "': " + ec.message());
  }
  FsyncPath(run_dir, /*directory=*/true);
  AtomicWriteFile(paths.config(), DumpYaml(config.ToJson()));
  impl->metrics_log = std::make_unique<RunLog>(run_dir, "metrics");
  impl->eval_log = std::make_unique<RunLog>(run_dir, "eval");
  impl->metrics_log->TruncateAfter(0);
  impl->eval_log->TruncateAfter(0);
  if (impl->eval_tasks) {
    impl->meta_test_log = std::make_unique<RunLog>(run_dir, "meta_test");
    impl->meta_test_log->TruncateAfter(0);
    impl->meta_train_log = std::make_unique<RunLog>(run_dir, "meta_train");
    impl->meta_train_log->TruncateAfter(0);
  }
  return Trainer(std::move(impl));
}

Trainer Trainer::Resume(const fs::path& run_dir, bool restart) {
  std::unique_ptr<RunLock> lock;
  if (fs::is_directory(run_dir)) lock = std::make_unique<RunLock>(run_dir);
  if (lock) RemoveStaleTemporaries(run_dir);
  RunInfo info = RunInfo::Read(run_dir);
  auto impl = std::make_unique<Impl>();
  impl->lock = std::move(lock);
  impl->Setup(info.config, std::move(info.tasks), std::move(info.eval_tasks), run_dir);
  std::optional<ChosenCheckpoint> chosen;
  std::string none;  // why there is nothing to resume from
  try {
    chosen = ChooseCheckpoint(run_dir);
  } catch (const ConfigError& e) {
    none = e.what();
  } catch (const Error& e) {
    if (!restart) throw;
    none = e.what();
  }
  if (chosen && restart) {
    throw ConfigError("run '" + run_dir.string() + "' has an intact checkpoint (" +
                      chosen->dir.filename().string() + "); resume it without --restart");
  }
  // Killed before its first checkpoint: checkpoints/ is still the empty
  // directory Create made and the run never finished. Starting again from
  // step 0 redoes exactly what was lost.
  std::error_code empty_ec;
  const bool never_checkpointed =
      !chosen && fs::is_directory(fs::symlink_status(impl->paths.checkpoints())) &&
      fs::is_empty(impl->paths.checkpoints(), empty_ec) && !empty_ec &&
      !fs::exists(impl->paths.summary());
  if (never_checkpointed && !restart) {
    impl->warnings.push_back("run '" + run_dir.string() +
                             "' stopped before its first checkpoint; starting it again from step 0");
  } else if (!chosen && !restart) {
    throw ConfigError(none + ", so there is nothing to resume; `manyworlds train --resume " +
                      run_dir.string() + " --restart` trains it again from step 0 with its " +
                      "saved config");
  }
  if (chosen) {
    impl->warnings = chosen->warnings;
    impl->LoadCheckpoint(chosen->dir);
  } else {
    // keep whatever was there (damaged checkpoints, a stray file) beside the run
    const fs::path old = impl->paths.checkpoints();
    if (!never_checkpointed && fs::exists(fs::symlink_status(old))) {
      fs::path aside;
      for (int n = 1;; ++n) {
        aside = run_dir / ("checkpoints.damaged." + std::to_string(n));
        if (!fs::exists(fs::symlink_status(aside))) break;
      }
      fs::rename(old, aside);
      impl->warnings.push_back("moved '" + old.string() + "' to '" + aside.string() + "'");
    }
    fs::remove(impl->paths.summary());
  }
  // only now (everything loaded) drop the rows logged after the checkpoint
  impl->metrics_log = std::make_unique<RunLog>(run_dir, "metrics");
  impl->eval_log = std::make_unique<RunLog>(run_dir, "eval");
  impl->metrics_log->TruncateAfter(impl->step);
  impl->eval_log->TruncateAfter(impl->step);
  if (impl->eval_tasks) {
    impl->meta_test_log = std::make_unique<RunLog>(run_dir, "meta_test");
    impl->meta_test_log->TruncateAfter(impl->step);
    impl->meta_train_log = std::make_unique<RunLog>(run_dir, "meta_train");
    impl->meta_train_log->TruncateAfter(impl->step);
  }
  return Trainer(std::move(impl));
}

TrainSummary Trainer::Run(const TrainCallbacks& callbacks) { return impl_->Run(callbacks); }
const TrainConfig& Trainer::config() const { return impl_->config; }
const TaskSet& Trainer::tasks() const { return impl_->tasks; }
int64_t Trainer::step() const { return impl_->step; }
const fs::path& Trainer::run_dir() const { return impl_->paths.dir; }
const std::vector<std::string>& Trainer::warnings() const { return impl_->warnings; }

}  // namespace manyworlds::experiments
