#include "manyworlds/experiments/trainer.h"

#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "manyworlds/core/atomic_file.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/executor.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"
#include "manyworlds/experiments/algorithm.h"
#include "manyworlds/experiments/algorithms.h"
#include "manyworlds/experiments/evaluation/meta_test_protocol.h"
#include "manyworlds/experiments/loops/collector.h"
#include "manyworlds/experiments/run/checkpoint_integrity.h"
#include "manyworlds/experiments/run/run_dir.h"
#include "manyworlds/experiments/run/run_lock.h"
#include "manyworlds/experiments/run/run_log.h"
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

// True when a multiple of `every` lies in (prev, step].
bool Due(int64_t prev, int64_t step, int64_t every) {
  return every > 0 && step / every != prev / every;
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
  // the collector's envs are the only ones built for the training tasks: their facts come from them
  collector = std::make_unique<Collector>(tasks, registry, config.env.envs_per_task,
                                          config.experiment.num_threads);
  facts = collector->facts();
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
  evaluator = std::make_unique<Evaluator>(tasks, registry, config.experiment.eval_episodes,
                                          MixSeed(config.experiment.seed, kEvalSeedStream),
                                          config.experiment.num_threads, &facts);
  evaluator->TerminateOnSuccess(config.experiment.eval_terminate_on_success);
  if (eval_tasks) {
    meta_test =
        std::make_unique<MetaTestProtocol>(*eval_tasks, registry, config.meta_test,
                                           MixSeed(config.experiment.seed, kMetaTestSeedStream),
                                           config.experiment.num_threads);
    CheckEvalFacts(meta_test->facts(), facts);
    meta_test->SetHeldOut(true);
    meta_train = std::make_unique<MetaTestProtocol>(
        tasks, registry, config.meta_test, MixSeed(config.experiment.seed, kMetaTrainSeedStream),
        config.experiment.num_threads, &facts);
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
      // the reduction order of products depends on these: resume checks them
      {"threads", ThreadRecord()},
  };
  return WriteCheckpoint(paths.dir, step, config.experiment.keep_checkpoints, std::move(state),
                         [&](const fs::path& dir, nlohmann::json& s) { algorithm->Save(dir, s); });
}

// A product's rounding depends on how many threads share it (measured: the
// same seed gave -85.28154 with one OpenBLAS thread and -85.28158 with two),
// so a run resumes exactly only with the thread counts it was trained with.
void Trainer::Impl::CheckThreads(const fs::path& dir, const nlohmann::json& state) {
  if (!state.contains("threads") || !state["threads"].is_object()) return;  // older checkpoints
  const nlohmann::json& saved = state["threads"];
  const nn::ThreadInfo now = nn::CurrentThreads();
  if (const auto mismatch = ThreadCountMismatch(dir, saved)) {
    throw ConfigError(*mismatch + ", so the resumed numbers would not match an uninterrupted run; "
                      "resume with OPENBLAS_NUM_THREADS=" +
                      std::to_string(saved.value("blas_threads", int64_t{-1})) +
                      " (and the run's own config)");
  }
  // what rounds differently from the checkpoint's machine: a warning, not an error
  auto warn_if_changed = [&](const char* key, const std::string& before_records,
                             const std::string& now_value, const std::string& what,
                             const std::string& here, const std::string& hint = "") {
    const std::string then = saved.value(key, before_records);
    if (then == now_value) return;
    warnings.push_back("checkpoint '" + dir.string() + "' was written with " + what + " '" + then +
                       "', " + here + " '" + now_value + "'" + hint +
                       ": the numbers will differ from an uninterrupted run in the last digits");
  };
  warn_if_changed("blas_core", "unknown", now.blas_core, "OpenBLAS kernels", "this machine uses");
  // checkpoints from before the oneDNN products ran every product on the BLAS
  warn_if_changed("gemm", "blas", now.gemm, "products on", "this program runs them on",
                  " (MANYWORLDS_GEMM)");
}

void Trainer::Impl::LoadCheckpoint(const fs::path& dir) {
  const nlohmann::json state = ReadCheckpointState(dir);
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

void NameMemorySettingsOnFailure(const std::function<void()>& work) {
  static const std::string kSettings =
      "lower agent.batch_size, agent.hidden_dim, replay.capacity or env.envs_per_task";
  try {
    work();
  } catch (const std::bad_alloc&) {
    throw Error("out of memory; " + kSettings);
  } catch (const c10::Error& e) {
    std::string what = e.what_without_backtrace();
    what = what.substr(0, what.find('\n'));
    const bool memory = what.find("not enough memory") != std::string::npos ||
                        what.find("can't allocate memory") != std::string::npos ||
                        what.find("out of memory") != std::string::npos;
    if (!memory) throw Error(what);  // still one line
    // "[enforce fail at alloc_cpu.cpp:75] err == 0. DefaultCPUAllocator: can't allocate memory:
    // you tried to allocate N bytes. Error code 12 (...)": the request is what a user can act on
    const size_t from = what.find("you tried to allocate");
    const size_t to = what.find("bytes", from);
    const std::string asked = from == std::string::npos || to == std::string::npos
                                  ? what
                                  : what.substr(from, to + 5 - from);
    throw Error("out of memory (" + asked + "); " + kSettings);
  }
}

Trainer Trainer::Create(const TrainConfig& config) {
  config.Validate();
  const fs::path run_dir = config.experiment.run_dir;
  RefuseExistingRun(run_dir);
  TaskSet tasks = ResolveTasks(config.env, DefaultRegistry());
  std::optional<TaskSet> held_out;
  if (config.eval_env) {
    try {
      held_out = ResolveTasks(*config.eval_env, DefaultRegistry(), "eval_env");
    } catch (const ConfigError& e) {
      throw ConfigError(std::string("eval_env: ") + e.what());
    }
  }
  auto impl = std::make_unique<Impl>();
  impl->Setup(config, std::move(tasks), std::move(held_out), run_dir);
  if (!config.experiment.init_from.empty()) {
    // fine-tuning: the learner starts from another run's checkpoint (a
    // resumed run reads its own checkpoints instead)
    fs::path from = config.experiment.init_from;
    // the integrity checks of resume and eval (state.json, the size and CRC of every file);
    // a run directory stands for its newest intact checkpoint. The source run's config may
    // differ from this one's: fine-tuning changes it.
    const bool is_run = fs::exists(from / "config.yaml");
    if (!is_run && !fs::exists(from / "learner.pt")) {
      throw ConfigError("experiment.init_from: '" + from.string() +
                        "' is not a checkpoint directory (no learner.pt) or a run directory");
    }
    try {
      if (is_run) from = ChooseCheckpoint(from).dir;
    } catch (const std::exception& e) {
      throw ConfigError(std::string("experiment.init_from: ") + e.what());
    }
    if (const auto problem = CheckpointProblem(from)) {
      throw ConfigError("experiment.init_from: checkpoint '" + from.string() + "' is damaged: " +
                        *problem);
    }
    try {
      impl->algorithm->LoadPolicy(from);
    } catch (const std::exception& e) {
      throw ConfigError("experiment.init_from: cannot start from '" + from.string() +
                        "' (same algorithm and network sizes needed): " + e.what());
    }
  }
  // nothing is created before the config has proved runnable; a directory
  // is a run once it has config.yaml, written last
  impl->lock = CreateRunDirectory(run_dir, config, impl->tasks, impl->eval_tasks);
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
