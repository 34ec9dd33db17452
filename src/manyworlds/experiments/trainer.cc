#include "manyworlds/experiments/trainer.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <ATen/CPUGeneratorImpl.h>

#include "manyworlds/agents/replay_buffer.h"
#include "manyworlds/agents/sac.h"
#include "manyworlds/config/atomic_file.h"
#include "manyworlds/config/yaml.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/executor.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"
#include "manyworlds/experiments/run_log.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Independent random streams derived from experiment.seed.
constexpr uint64_t kAgentStream = 0x6167656e74;     // "agent"
constexpr uint64_t kActionStream = 0x616374696f6e;  // "action"
constexpr uint64_t kReplayStream = 0x7265706c6179;  // "replay"
constexpr uint64_t kTorchStream = 0x746f726368;     // "torch"
constexpr uint64_t kRoundStream = 0x726f756e64;     // "round"

constexpr char kCheckpointFormat[] = "manyworlds-train-checkpoint";
constexpr int kCheckpointVersion = 1;
constexpr char kLatestFile[] = "latest";

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// True when a multiple of `every` lies in (prev, step].
bool Due(int64_t prev, int64_t step, int64_t every) {
  return every > 0 && step / every != prev / every;
}

std::string CheckpointName(int64_t step) {
  char name[32];
  std::snprintf(name, sizeof(name), "step_%012lld", static_cast<long long>(step));
  return name;
}

void FsyncPath(const fs::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The first line of a (possibly multi-line) c10 error message.
std::string FirstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

at::Generator& DefaultTorchGenerator() {
  static at::Generator generator = at::detail::getDefaultCPUGenerator();
  return generator;
}

torch::Tensor GeneratorState(at::Generator& generator) {
  std::lock_guard<std::mutex> lock(generator.mutex());
  return generator.get_state();
}

void SetGeneratorState(at::Generator& generator, const torch::Tensor& state) {
  std::lock_guard<std::mutex> lock(generator.mutex());
  generator.set_state(state);
}

agents::SacConfig LearnerConfig(const TrainConfig& config) {
  agents::SacConfig agent = config.agent;
  agent.seed = MixSeed(MixSeed(config.experiment.seed, kAgentStream), config.agent.seed);
  return agent;
}

// Loads learner.pt into a learner (and, if given, the trainer's generators).
void LoadLearnerArchive(const fs::path& file, agents::SacLearner& learner,
                        at::Generator* replay_generator) {
  if (!fs::exists(file)) throw Error("checkpoint file '" + file.string() + "' is missing");
  try {
    torch::serialize::InputArchive archive;
    archive.load_from(file.string());
    learner.Load(archive);
    if (replay_generator != nullptr) {
      torch::Tensor replay_state, torch_state;
      archive.read("replay_generator", replay_state);
      archive.read("torch_generator", torch_state);
      SetGeneratorState(*replay_generator, replay_state);
      SetGeneratorState(DefaultTorchGenerator(), torch_state);
    }
  } catch (const Error& e) {
    throw Error("checkpoint '" + file.string() + "': " + e.what());
  } catch (const std::exception& e) {
    throw Error("checkpoint '" + file.string() + "' is corrupt or incompatible: " +
                FirstLine(e.what()));
  }
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

// Mean of each learner metric over a round's updates, in first-seen order.
class MetricMeans {
 public:
  void Add(const agents::Metrics& m) {
    for (const auto& [name, value] : m.items()) {
      auto it = std::find_if(sums_.begin(), sums_.end(),
                             [&](const auto& s) { return s.first == name; });
      if (it == sums_.end()) {
        sums_.emplace_back(name, 0.0);
        counts_.push_back(0);
        it = sums_.end() - 1;
      }
      it->second += value;
      ++counts_[it - sums_.begin()];
    }
  }
  void WriteTo(nlohmann::json& row) const {
    for (size_t i = 0; i < sums_.size(); ++i) row[sums_[i].first] = sums_[i].second / counts_[i];
  }
  void Clear() {
    sums_.clear();
    counts_.clear();
  }

 private:
  std::vector<std::pair<std::string, double>> sums_;
  std::vector<int64_t> counts_;
};

}  // namespace

nlohmann::json TrainSummary::ToJson() const {
  return {{"finished", finished},
          {"step", step},
          {"updates", updates},
          {"wall_s", wall_s},
          {"env_steps_per_s", env_steps_per_s},
          {"updates_per_s", updates_per_s},
          {"final_eval", OptionalEval(final_eval)}};
}

fs::path LatestCheckpoint(const fs::path& run_dir) {
  const fs::path dir = RunPaths{run_dir}.checkpoints();
  const fs::path latest = dir / kLatestFile;
  if (fs::exists(latest)) {
    std::string name = ReadText(latest);
    while (!name.empty() && (name.back() == '\n' || name.back() == ' ')) name.pop_back();
    if (name.find('/') == std::string::npos && fs::is_directory(dir / name)) return dir / name;
  }
  std::vector<fs::path> found;
  if (fs::is_directory(dir)) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (entry.is_directory() && name.rfind("step_", 0) == 0) found.push_back(entry.path());
    }
  }
  if (found.empty()) throw ConfigError("run '" + run_dir.string() + "' has no checkpoint yet");
  std::sort(found.begin(), found.end());
  return found.back();
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
  return info;
}

EvalResult EvaluateCheckpoint(const RunInfo& run, const fs::path& checkpoint, int64_t episodes) {
  const Registry& registry = DefaultRegistry();
  const EnvFacts facts = InspectEnvs(run.tasks, registry);
  agents::SacLearner learner(LearnerConfig(run.config), facts.obs_dim, facts.action_dim,
                             run.tasks.size());
  LoadLearnerArchive(checkpoint / "learner.pt", learner, nullptr);
  Evaluator evaluator(run.tasks, registry, episodes, MixSeed(run.config.experiment.seed,
                                                             kEvalSeedStream),
                      run.config.experiment.num_threads);
  EvalResult result = evaluator.Run([&](const torch::Tensor& obs, const torch::Tensor& task) {
    return learner.Act(obs, task, /*deterministic=*/true);
  });
  // the step the checkpoint was taken at
  try {
    const auto state = nlohmann::json::parse(ReadText(checkpoint / "state.json"));
    result.step = state.at("step").get<int64_t>();
  } catch (const std::exception&) {
    result.step = 0;
  }
  return result;
}

struct Trainer::Impl {
  RunPaths paths;
  TrainConfig config;
  TaskSet tasks;
  EnvFacts facts;
  const Registry& registry = DefaultRegistry();

  int64_t num_tasks = 0;
  int64_t num_envs = 0;
  int64_t envs_per_task = 0;
  int64_t round_length = 0;
  int64_t total_steps = 0;
  int64_t batch_size = 0;
  agents::ReplaySampling sampling = agents::ReplaySampling::kBalanced;

  std::unique_ptr<BatchedExecutor> exec;
  std::unique_ptr<agents::SacLearner> learner;
  std::unique_ptr<agents::ReplayBuffer> replay;
  at::Generator replay_generator;
  Rng action_rng;
  std::unique_ptr<Evaluator> evaluator;
  std::unique_ptr<RunLog> metrics_log;
  std::unique_ptr<RunLog> eval_log;

  // counters (checkpointed)
  int64_t step = 0;
  int64_t round = 0;
  int64_t updates = 0;
  double wall_before = 0.0;  // wall time of earlier sessions
  std::optional<EvalResult> last_eval;

  // per-step buffers
  torch::Tensor env_task;        // (num_envs) int64 task of each env
  std::vector<float> obs;        // (num_envs x obs_dim) observation acted on
  std::vector<float> unit;       // (num_envs x action_dim) actions in (-1, 1)
  std::vector<float> env_action; // (num_envs x action_dim) scaled to the box
  std::vector<double> ep_return; // (num_envs)
  std::vector<char> ep_success;  // (num_envs)

  void Setup(const TrainConfig& c, TaskSet t, const fs::path& run_dir);
  void BeginRound();
  void Act();
  void StepEnvs(double& round_return, double& round_success, int64_t& round_episodes);
  EvalResult Evaluate();
  fs::path SaveCheckpoint();
  void LoadCheckpoint(const fs::path& dir);
  TrainSummary Run(const TrainCallbacks& callbacks);
};

void Trainer::Impl::Setup(const TrainConfig& c, TaskSet t, const fs::path& run_dir) {
  config = c;
  tasks = std::move(t);
  paths = RunPaths{run_dir};
  facts = InspectEnvs(tasks, registry);
  num_tasks = tasks.size();
  envs_per_task = config.env.envs_per_task;
  num_envs = num_tasks * envs_per_task;
  round_length = facts.episode_length;
  const int64_t rounds = (config.experiment.steps_per_task + round_length - 1) / round_length;
  total_steps = rounds * round_length;
  batch_size = config.TotalBatchSize(num_tasks);
  sampling = config.sampling();
  if (sampling == agents::ReplaySampling::kBalanced && batch_size % num_tasks != 0) {
    throw ConfigError("balanced replay sampling needs the batch size (" +
                      std::to_string(batch_size) + ") to be a multiple of the number of tasks (" +
                      std::to_string(num_tasks) + "); set experiment.batch_size");
  }
  if (config.replay.capacity < num_tasks) {
    throw ConfigError("'replay.capacity' (" + std::to_string(config.replay.capacity) +
                      ") must be at least the number of tasks (" + std::to_string(num_tasks) +
                      ")");
  }

  const uint64_t seed = config.experiment.seed;
  torch::manual_seed(MixSeed(seed, kTorchStream));
  learner = std::make_unique<agents::SacLearner>(LearnerConfig(config), facts.obs_dim,
                                                 facts.action_dim, num_tasks);
  replay = std::make_unique<agents::ReplayBuffer>(config.replay.capacity, facts.obs_dim,
                                                  facts.action_dim, num_tasks);
  replay_generator = at::detail::createCPUGenerator(MixSeed(seed, kReplayStream));
  action_rng.Seed(MixSeed(seed, kActionStream));

  std::vector<std::unique_ptr<Env>> envs;
  for (int64_t i = 0; i < num_envs; ++i) envs.push_back(tasks.MakeEnv(i / envs_per_task, registry));
  exec = std::make_unique<BatchedExecutor>(
      std::move(envs),
      ExecutorOptions{.num_threads = config.experiment.num_threads, .auto_reset = true});
  evaluator = std::make_unique<Evaluator>(tasks, registry, config.experiment.eval_episodes,
                                          MixSeed(seed, kEvalSeedStream),
                                          config.experiment.num_threads);

  env_task = torch::empty({num_envs}, torch::kInt64);
  for (int64_t i = 0; i < num_envs; ++i) env_task[i] = i / envs_per_task;
  obs.assign(num_envs * facts.obs_dim, 0.0f);
  unit.assign(num_envs * facts.action_dim, 0.0f);
  env_action.assign(num_envs * facts.action_dim, 0.0f);
  ep_return.assign(num_envs, 0.0);
  ep_success.assign(num_envs, 0);
}

void Trainer::Impl::BeginRound() {
  // every env starts an episode whose seeds and variation depend only on
  // (seed, round, env): nothing of the previous round carries over
  const uint64_t base = MixSeed(MixSeed(config.experiment.seed, kRoundStream), round);
  for (int64_t i = 0; i < num_envs; ++i) {
    Rng r(MixSeed(base, i));
    Env& env = exec->env(static_cast<int>(i));
    env.Seed(r.NextU64());
    env.SeedTask(r.NextU64());
    const auto& variations = tasks.tasks[i / envs_per_task].variations;
    const uint64_t v = variations.size() > 1 ? r.UniformInt(variations.size()) : 0;
    exec->SetTaskState(static_cast<int>(i), variations[v]);
    ep_return[i] = 0.0;
    ep_success[i] = 0;
  }
}

void Trainer::Impl::Act() {
  const auto current = exec->env_obs();
  std::copy(current.begin(), current.end(), obs.begin());
  if (step < config.experiment.warmup_steps) {
    for (float& a : unit) a = static_cast<float>(action_rng.Uniform(-1.0, 1.0));
  } else {
    const torch::Tensor o = torch::from_blob(obs.data(), {num_envs, facts.obs_dim},
                                             torch::kFloat32);
    const torch::Tensor a = learner->Act(o, env_task, /*deterministic=*/false).contiguous();
    std::copy(a.data_ptr<float>(), a.data_ptr<float>() + a.numel(), unit.begin());
  }
  ScaleActions(unit.data(), num_envs, facts, env_action.data());
}

void Trainer::Impl::StepEnvs(double& round_return, double& round_success,
                             int64_t& round_episodes) {
  exec->Step(env_action);
  const int64_t d = facts.obs_dim;
  const int64_t a = facts.action_dim;
  const auto next = exec->env_obs();
  const auto final_obs = exec->final_env_obs();
  const auto rewards = exec->rewards();
  const auto terminated = exec->terminated();
  const auto truncated = exec->truncated();
  const auto info = exec->info();
  const int64_t info_size = static_cast<int64_t>(exec->info_fields().size());
  for (int64_t i = 0; i < num_envs; ++i) {
    const bool ended = terminated[i] || truncated[i];
    const float* next_row = (ended ? final_obs.data() : next.data()) + i * d;
    replay->Add(i / envs_per_task, {obs.data() + i * d, static_cast<size_t>(d)},
                {unit.data() + i * a, static_cast<size_t>(a)}, rewards[i],
                {next_row, static_cast<size_t>(d)}, terminated[i]);
    ep_return[i] += rewards[i];
    if (facts.success_index >= 0 && info[i * info_size + facts.success_index] > 0.5f) {
      ep_success[i] = 1;
    }
    if (ended) {
      round_return += ep_return[i];
      round_success += ep_success[i];
      ++round_episodes;
      ep_return[i] = 0.0;
      ep_success[i] = 0;
    }
  }
}

EvalResult Trainer::Impl::Evaluate() {
  EvalResult result = evaluator->Run([&](const torch::Tensor& o, const torch::Tensor& task) {
    return learner->Act(o, task, /*deterministic=*/true);
  });
  result.step = step;
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
  try {
    torch::serialize::OutputArchive archive;
    learner->Save(archive);
    archive.write("replay_generator", GeneratorState(replay_generator));
    archive.write("torch_generator", GeneratorState(DefaultTorchGenerator()));
    archive.save_to((tmp / "learner.pt").string());
  } catch (const std::exception& e) {
    throw Error("cannot write checkpoint '" + (tmp / "learner.pt").string() +
                "': " + FirstLine(e.what()));
  }
  replay->SaveFile(tmp / "replay.bin");
  nlohmann::json rng = nlohmann::json::array();
  for (uint64_t word : action_rng.state()) rng.push_back(std::to_string(word));
  const nlohmann::json state = {
      {"format", kCheckpointFormat},
      {"version", kCheckpointVersion},
      {"step", step},
      {"round", round},
      {"updates", updates},
      {"wall_s", wall_before},
      {"num_tasks", num_tasks},
      {"num_envs", num_envs},
      {"obs_dim", facts.obs_dim},
      {"action_dim", facts.action_dim},
      {"action_rng", rng},
      {"last_eval", OptionalEval(last_eval)},
  };
  AtomicWriteFile(tmp / "state.json", state.dump(2) + "\n");
  FsyncPath(tmp / "learner.pt", false);
  FsyncPath(tmp / "replay.bin", false);
  FsyncPath(tmp, true);
  fs::remove_all(final_dir);
  fs::rename(tmp, final_dir);
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

void Trainer::Impl::LoadCheckpoint(const fs::path& dir) {
  nlohmann::json state;
  try {
    state = nlohmann::json::parse(ReadText(dir / "state.json"));
  } catch (const std::exception& e) {
    throw Error("checkpoint '" + dir.string() + "': unreadable state.json: " +
                FirstLine(e.what()));
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
  expect("version", kCheckpointVersion);
  expect("num_tasks", num_tasks);
  expect("num_envs", num_envs);
  expect("obs_dim", facts.obs_dim);
  expect("action_dim", facts.action_dim);
  Rng::State rng{};
  int64_t new_step = 0, new_round = 0, new_updates = 0;
  double new_wall = 0.0;
  std::optional<EvalResult> new_eval;
  try {
    const auto& words = state.at("action_rng");
    if (!words.is_array() || words.size() != rng.size()) throw Error("action_rng");
    for (size_t i = 0; i < rng.size(); ++i) rng[i] = std::stoull(words[i].get<std::string>());
    new_step = state.at("step").get<int64_t>();
    new_round = state.at("round").get<int64_t>();
    new_updates = state.at("updates").get<int64_t>();
    new_wall = state.at("wall_s").get<double>();
    new_eval = EvalFromJson(state.at("last_eval"));
  } catch (const std::exception& e) {
    throw Error("checkpoint '" + dir.string() + "': malformed state.json (" +
                FirstLine(e.what()) + ")");
  }
  if (new_step < 0 || new_step > total_steps || new_step != new_round * round_length) {
    throw Error("checkpoint '" + dir.string() + "': step " + std::to_string(new_step) +
                " is not a round boundary of this run");
  }
  LoadLearnerArchive(dir / "learner.pt", *learner, &replay_generator);
  replay->LoadFile(dir / "replay.bin");
  action_rng.set_state(rng);
  step = new_step;
  round = new_round;
  updates = new_updates;
  wall_before = new_wall;
  last_eval = std::move(new_eval);
}

TrainSummary Trainer::Impl::Run(const TrainCallbacks& callbacks) {
  const auto session_start = Clock::now();
  const int64_t session_start_step = step;
  const int64_t session_start_updates = updates;
  const double utd = config.experiment.updates_per_step;
  const int64_t warmup = config.experiment.warmup_steps;
  MetricMeans means;

  auto progress = [&]() {
    TrainProgress p;
    p.step = step;
    p.total_steps = total_steps;
    p.updates = updates;
    const double session = Seconds(Clock::now() - session_start);
    p.elapsed_s = wall_before + session;
    if (session > 0) {
      p.env_steps_per_s = static_cast<double>((step - session_start_step) * num_envs) / session;
      p.updates_per_s = static_cast<double>(updates - session_start_updates) / session;
    }
    p.last_eval = last_eval;
    return p;
  };

  bool stopped = false;
  while (step < total_steps && !stopped) {
    const auto round_start = Clock::now();
    const int64_t round_start_updates = updates;
    double t_act = 0.0, t_env = 0.0, t_update = 0.0;
    double round_return = 0.0, round_success = 0.0;
    int64_t round_episodes = 0;
    means.Clear();
    BeginRound();
    for (int64_t s = 0; s < round_length; ++s) {
      auto t0 = Clock::now();
      Act();
      auto t1 = Clock::now();
      StepEnvs(round_return, round_success, round_episodes);
      auto t2 = Clock::now();
      ++step;
      if (step > warmup) {
        const double exact = static_cast<double>(step - warmup) * utd;
        const double nearest = std::round(exact);
        const auto target = static_cast<int64_t>(
            std::abs(exact - nearest) < 1e-9 ? nearest : std::floor(exact));
        while (updates < target) {
          const agents::Batch& batch = replay->Sample(batch_size, sampling, replay_generator);
          means.Add(learner->Update(batch));
          ++updates;
        }
      }
      auto t3 = Clock::now();
      t_act += Seconds(t1 - t0);
      t_env += Seconds(t2 - t1);
      t_update += Seconds(t3 - t2);
    }
    ++round;
    const double round_wall = Seconds(Clock::now() - round_start);

    nlohmann::json row = {
        {"step", step},
        {"round", round},
        {"env_steps", step * num_envs},
        {"updates", updates},
        {"wall_s", wall_before + Seconds(Clock::now() - session_start)},
        {"env_steps_per_s", static_cast<double>(round_length * num_envs) / round_wall},
        {"updates_per_s", static_cast<double>(updates - round_start_updates) / round_wall},
        {"time_act_s", t_act},
        {"time_env_s", t_env},
        {"time_update_s", t_update},
        {"buffer_size", replay->size()},
        {"train_episodes", round_episodes},
        {"train_return",
         round_episodes > 0 ? nlohmann::json(round_return / round_episodes) : nlohmann::json()},
        {"train_success", round_episodes > 0 && facts.success_index >= 0
                              ? nlohmann::json(round_success / round_episodes)
                              : nlohmann::json()},
    };
    means.WriteTo(row);
    metrics_log->Append(row);

    const int64_t prev = step - round_length;
    const bool last = step >= total_steps;
    if (last || Due(prev, step, config.experiment.eval_every)) {
      last_eval = Evaluate();
      eval_log->Append(last_eval->ToJson());
      if (callbacks.on_eval) callbacks.on_eval(*last_eval);
    }
    if (last || Due(prev, step, config.experiment.checkpoint_every)) {
      // wall time so far, so that a resumed run keeps counting
      const double before = wall_before;
      wall_before += Seconds(Clock::now() - session_start);
      const fs::path saved = SaveCheckpoint();
      wall_before = before;
      if (callbacks.on_checkpoint) callbacks.on_checkpoint(saved);
      if (callbacks.stop_after_step && step >= *callbacks.stop_after_step) stopped = true;
    }
    if (callbacks.on_round) callbacks.on_round(progress());
  }

  const TrainProgress p = progress();
  TrainSummary summary;
  summary.finished = step >= total_steps;
  summary.step = step;
  summary.updates = updates;
  summary.wall_s = p.elapsed_s;
  summary.env_steps_per_s = p.env_steps_per_s;
  summary.updates_per_s = p.updates_per_s;
  summary.final_eval = last_eval;
  if (summary.finished) {
    nlohmann::json json = summary.ToJson();
    json["run_dir"] = paths.dir.string();
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
  if (fs::exists(paths.config()) || fs::exists(paths.checkpoints())) {
    throw ConfigError("run directory '" + run_dir.string() +
                      "' already holds a run; continue it with `manyworlds train --resume " +
                      run_dir.string() + "` or choose another experiment.run_dir");
  }
  TaskSet tasks = ResolveTasks(config.env, DefaultRegistry());
  auto impl = std::make_unique<Impl>();
  impl->Setup(config, std::move(tasks), run_dir);
  std::error_code ec;
  fs::create_directories(run_dir, ec);
  if (ec) {
    throw Error("cannot create run directory '" + run_dir.string() + "': " + ec.message());
  }
  AtomicWriteFile(paths.config(), DumpYaml(config.ToJson()));
  AtomicWriteFile(paths.tasks(), impl->tasks.ToJson().dump(2) + "\n");
  impl->metrics_log = std::make_unique<RunLog>(run_dir, "metrics");
  impl->eval_log = std::make_unique<RunLog>(run_dir, "eval");
  impl->metrics_log->TruncateAfter(0);
  impl->eval_log->TruncateAfter(0);
  return Trainer(std::move(impl));
}

Trainer Trainer::Resume(const fs::path& run_dir) {
  RunInfo info = RunInfo::Read(run_dir);
  auto impl = std::make_unique<Impl>();
  impl->Setup(info.config, std::move(info.tasks), run_dir);
  std::optional<fs::path> checkpoint;
  try {
    checkpoint = LatestCheckpoint(run_dir);
  } catch (const ConfigError&) {
    // stopped before its first checkpoint: start over
  }
  if (checkpoint) impl->LoadCheckpoint(*checkpoint);
  // only now (everything loaded) drop the rows logged after the checkpoint
  impl->metrics_log = std::make_unique<RunLog>(run_dir, "metrics");
  impl->eval_log = std::make_unique<RunLog>(run_dir, "eval");
  impl->metrics_log->TruncateAfter(impl->step);
  impl->eval_log->TruncateAfter(impl->step);
  return Trainer(std::move(impl));
}

TrainSummary Trainer::Run(const TrainCallbacks& callbacks) { return impl_->Run(callbacks); }
const TrainConfig& Trainer::config() const { return impl_->config; }
const TaskSet& Trainer::tasks() const { return impl_->tasks; }
int64_t Trainer::step() const { return impl_->step; }
const fs::path& Trainer::run_dir() const { return impl_->paths.dir; }

}  // namespace manyworlds::experiments
