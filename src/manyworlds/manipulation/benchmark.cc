#include "manyworlds/manipulation/benchmark.h"

#include <algorithm>
#include <functional>
#include <set>
#include <unordered_map>

#include "manyworlds/core/hash.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/core/wrapper.h"
#include "manyworlds/core/wrappers/append_task_one_hot.h"
#include "manyworlds/manipulation/manipulation.h"

namespace manyworlds::manipulation {
namespace {

// FNV-1a: a task's variations depend on its name, not on its position in a
// benchmark, and the hash is the same on every platform.
uint64_t NameHash(std::string_view name) { return Fnv1a(name.data(), name.size()); }

SawyerOptions MemberOptions(const BenchmarkConfig& config) {
  SawyerOptions options;
  options.goal_observable = !config.meta;
  options.reward_version = config.reward_version;
  return options;
}

std::vector<std::unique_ptr<SawyerTask>> MakeMembers(const BenchmarkConfig& config) {
  if (config.tasks.empty()) {
    throw ConfigError("benchmark '" + config.id + "' needs at least one task");
  }
  if (config.num_variations < 1) {
    throw ConfigError("benchmark '" + config.id + "': num_variations must be >= 1, got " +
                      std::to_string(config.num_variations));
  }
  std::set<std::string> seen;
  std::vector<std::unique_ptr<SawyerTask>> members;
  const SawyerOptions options = MemberOptions(config);
  for (const std::string& task : config.tasks) {
    if (!seen.insert(task).second) {
      throw ConfigError("benchmark '" + config.id + "' lists task '" + task + "' twice");
    }
    members.push_back(MakeSawyerTask(task, options));
  }
  return members;
}

EnvSpec MakeSpec(const BenchmarkConfig& config,
                 const std::vector<std::unique_ptr<SawyerTask>>& members) {
  const EnvSpec& first = members.front()->spec();
  std::vector<float> low = first.env_obs_space.low();
  std::vector<float> high = first.env_obs_space.high();
  for (const auto& member : members) {
    const Space& box = member->spec().env_obs_space;
    for (size_t i = 0; i < low.size(); ++i) {
      low[i] = std::min(low[i], box.low()[i]);
      high[i] = std::max(high[i], box.high()[i]);
    }
  }
  EnvSpec spec;
  spec.id = config.id;
  std::string names;
  for (const std::string& task : config.tasks) names += (names.empty() ? "" : ", ") + task;
  spec.description = std::string(config.meta ? "meta-RL" : "multi-task") + " benchmark (" +
                     (config.split == BenchmarkSplit::kTrain ? "train" : "test") + " split, " +
                     std::to_string(config.num_variations) + " variations per task): " + names;
  spec.action_space = first.action_space;
  spec.env_obs_space = Space::Box(std::move(low), std::move(high), first.env_obs_space.shape());
  if (!config.meta) spec.task_obs_space = Space::Discrete(static_cast<int64_t>(members.size()));
  spec.info_fields = first.info_fields;
  spec.max_episode_steps = first.max_episode_steps;
  spec.uses_env_seed = false;
  return spec;
}

}  // namespace

const std::vector<BenchmarkSplits>& PublishedBenchmarks() {
  // Meta-World v3's env_dict.py: MT10_V3, MT25_V3, MT50_V3 (= ALL_V3_ENVIRONMENTS),
  // ML10_V3, ML25_V3, ML45_V3, in their order.
  static const std::vector<BenchmarkSplits> benchmarks = [] {
    const std::vector<std::string> mt10 = {
        "reach",       "push",         "pick-place",           "door-open",
        "drawer-open", "drawer-close", "button-press-topdown", "peg-insert-side",
        "window-open", "window-close"};
    std::vector<std::string> mt25 = mt10;
    for (const char* task :
         {"coffee-pull", "pick-out-of-hole", "disassemble", "pick-place-wall", "basketball",
          "stick-pull", "button-press-wall", "faucet-open", "door-lock", "lever-pull",
          "sweep-into", "faucet-close", "coffee-button", "button-press-topdown-wall",
          "dial-turn"}) {
      mt25.emplace_back(task);
    }
    const std::vector<std::string> all = {
        "assembly",         "basketball",          "bin-picking",
        "box-close",        "button-press-topdown", "button-press-topdown-wall",
        "button-press",     "button-press-wall",   "coffee-button",
        "coffee-pull",      "coffee-push",         "dial-turn",
        "disassemble",      "door-close",          "door-lock",
        "door-open",        "door-unlock",         "hand-insert",
        "drawer-close",     "drawer-open",         "faucet-open",
        "faucet-close",     "hammer",              "handle-press-side",
        "handle-press",     "handle-pull-side",    "handle-pull",
        "lever-pull",       "pick-place-wall",     "pick-out-of-hole",
        "pick-place",       "plate-slide",         "plate-slide-side",
        "plate-slide-back", "plate-slide-back-side", "peg-insert-side",
        "peg-unplug-side",  "soccer",              "stick-push",
        "stick-pull",       "push",                "push-wall",
        "push-back",        "reach",               "reach-wall",
        "shelf-place",      "sweep-into",          "sweep",
        "window-open",      "window-close"};
    const std::vector<std::string> ml45_test = {"bin-picking", "box-close", "hand-insert",
                                                "door-lock", "door-unlock"};
    // ML45_V3's train list is ALL_V3_ENVIRONMENTS without the test tasks, except that
    // push-back comes before pick-place and push-wall before push (v3's own order).
    const std::vector<std::string> ml45_train = {
        "assembly",          "basketball",        "button-press-topdown",
        "button-press-topdown-wall", "button-press", "button-press-wall",
        "coffee-button",     "coffee-pull",       "coffee-push",
        "dial-turn",         "disassemble",       "door-close",
        "door-open",         "drawer-close",      "drawer-open",
        "faucet-open",       "faucet-close",      "hammer",
        "handle-press-side", "handle-press",      "handle-pull-side",
        "handle-pull",       "lever-pull",        "pick-place-wall",
        "pick-out-of-hole",  "push-back",         "pick-place",
        "plate-slide",       "plate-slide-side",  "plate-slide-back",
        "plate-slide-back-side", "peg-insert-side", "peg-unplug-side",
        "soccer",            "stick-push",        "stick-pull",
        "push-wall",         "push",              "reach-wall",
        "reach",             "shelf-place",       "sweep-into",
        "sweep",             "window-open",       "window-close"};
    return std::vector<BenchmarkSplits>{
        {"mt10", "MT10: 10 tasks x 50 variations, goal visible", false, mt10, {}},
        {"mt25", "MT25: MT10 and 15 more tasks x 50 variations, goal visible", false, mt25, {}},
        {"mt50", "MT50: all 50 tasks x 50 variations, goal visible", false, all, {}},
        {"ml10", "ML10: 10 train tasks, 5 held-out test tasks, goal hidden", true,
         {"reach", "push", "pick-place", "door-open", "drawer-close", "button-press-topdown",
          "peg-insert-side", "window-open", "sweep", "basketball"},
         {"drawer-open", "door-close", "shelf-place", "sweep-into", "lever-pull"}},
        // v3's ML25 lists basketball among both its train and its test tasks; kept as v3
        // has it (docs/fidelity.md).
        {"ml25", "ML25: MT25's tasks for training, 5 test tasks, goal hidden", true, mt25,
         {"basketball", "door-close", "shelf-place", "sweep", "button-press"}},
        {"ml45", "ML45: 45 train tasks, 5 held-out test tasks, goal hidden", true, ml45_train,
         ml45_test},
    };
  }();
  return benchmarks;
}

const BenchmarkSplits& PublishedBenchmark(const std::string& id) {
  for (const BenchmarkSplits& b : PublishedBenchmarks()) {
    if (b.id == id) return b;
  }
  throw ConfigError("unknown benchmark '" + id +
                    "': allowed are mt10, mt25, mt50, ml10, ml25, ml45");
}

std::vector<std::string> Mt50Tasks() { return PublishedBenchmark("mt50").train; }
std::vector<std::string> Mt10Tasks() { return PublishedBenchmark("mt10").train; }
std::vector<std::string> Ml10TrainTasks() { return PublishedBenchmark("ml10").train; }
std::vector<std::string> Ml10TestTasks() { return PublishedBenchmark("ml10").test; }

Benchmark::Benchmark(BenchmarkConfig config)
    : Benchmark(config, MakeMembers(config)) {}

Benchmark::Benchmark(BenchmarkConfig config, std::vector<std::unique_ptr<SawyerTask>> members)
    : Env(MakeSpec(config, members)), config_(std::move(config)), members_(std::move(members)) {
  const uint64_t split_seed = config_.seed + (config_.split == BenchmarkSplit::kTest ? 1 : 0);
  for (size_t t = 0; t < members_.size(); ++t) {
    SawyerTask& member = *members_[t];
    member.SeedTask(MixSeed(split_seed, NameHash(config_.tasks[t])));
    std::vector<TaskState> drawn;
    std::set<std::string> seen;
    // Continuous ranges make repeats practically impossible; the bound only
    // guards against a task whose ranges collapse to a point.
    for (int attempt = 0; static_cast<int>(drawn.size()) < config_.num_variations; ++attempt) {
      if (attempt > 100 * config_.num_variations) {
        throw Error("benchmark '" + config_.id + "': task '" + config_.tasks[t] + "' has only " +
                    std::to_string(drawn.size()) + " distinct variations");
      }
      TaskState state = member.SampleTaskState();
      if (seen.insert(state.ToJson().dump()).second) drawn.push_back(std::move(state));
    }
    variations_.push_back(std::move(drawn));
  }
  member_task_obs_.assign(members_.front()->spec().task_obs_space.flat_size(), 0.0f);
  for (auto& member : members_) member.reset();
}

SawyerTask& Benchmark::Member(int task) const {
  auto& member = members_.at(task);
  if (!member) {
    member = MakeSawyerTask(config_.tasks[task], MemberOptions(config_));
    member->SetMaxEpisodeSteps(spec().max_episode_steps);
  }
  return *member;
}

TaskState Benchmark::VariationState(int task, int variation) const {
  if (task < 0 || task >= num_tasks()) {
    throw ConfigError("benchmark '" + id() + "': task index " + std::to_string(task) +
                      " outside [0, " + std::to_string(num_tasks()) + ")");
  }
  const auto& list = variations_[task];
  if (variation < 0 || variation >= static_cast<int>(list.size())) {
    throw ConfigError("benchmark '" + id() + "': variation " + std::to_string(variation) +
                      " outside [0, " + std::to_string(list.size()) + ")");
  }
  return TaskState{id(),
                   {{"task", config_.tasks[task]},
                    {"variation", variation},
                    {"state", list[variation].ToJson()}}};
}

std::vector<TaskGroup> Benchmark::EvaluationTasks() const {
  std::vector<TaskGroup> groups;
  for (int t = 0; t < num_tasks(); ++t) {
    TaskGroup group{config_.tasks[t], {}};
    for (int v = 0; v < static_cast<int>(variations_[t].size()); ++v) {
      group.states.push_back(VariationState(t, v));
    }
    groups.push_back(std::move(group));
  }
  return groups;
}

void Benchmark::SetMaxEpisodeSteps(int64_t max_episode_steps) {
  for (auto& member : members_) {
    if (member) member->SetMaxEpisodeSteps(max_episode_steps);
  }
  Env::SetMaxEpisodeSteps(max_episode_steps);  // members built later read it from spec()
}

TaskState Benchmark::DoSampleTaskState(Rng& task_rng) {
  const int task = static_cast<int>(task_rng.UniformInt(config_.tasks.size()));
  const int variation = static_cast<int>(task_rng.UniformInt(variations_[task].size()));
  return VariationState(task, variation);
}

TaskState Benchmark::DoGetTaskState() const {
  return VariationState(active_task_, active_variation_);
}

void Benchmark::DoSetTaskState(const TaskState& state) {
  TaskStateReader reader(state, id());
  reader.ExpectKeys({"task", "variation", "state"});
  const std::string prefix = "task state for benchmark '" + id() + "': ";
  const auto task_it = state.params.find("task");
  if (task_it == state.params.end() || !task_it->is_string()) {
    throw TaskStateError(prefix + "field 'task' must be a task name");
  }
  const std::string name = task_it->get<std::string>();
  const auto found = std::find(config_.tasks.begin(), config_.tasks.end(), name);
  if (found == config_.tasks.end()) {
    std::string allowed;
    for (const auto& t : config_.tasks) allowed += (allowed.empty() ? "" : ", ") + t;
    throw TaskStateError(prefix + "task '" + name + "' is not in this benchmark (" + allowed +
                         ")");
  }
  const int task = static_cast<int>(found - config_.tasks.begin());
  const int variation = static_cast<int>(
      reader.Integer("variation", 0, static_cast<int64_t>(variations_[task].size()) - 1));
  TaskState embedded;
  try {
    embedded = TaskState::FromJson(state.params.at("state"));
  } catch (const std::exception& e) {
    throw TaskStateError(prefix + "field 'state' is not a task state: " + e.what());
  }
  if (!(embedded.ToJson() == variations_[task][variation].ToJson())) {
    throw TaskStateError(prefix + "variation " + std::to_string(variation) + " of '" + name +
                         "' differs from this instance's (made with another benchmark seed "
                         "or split?)");
  }
  Member(task).SetTaskState(embedded);
  active_task_ = task;
  active_variation_ = variation;
  if (config_.meta) {
    SetTaskObs({});
  } else {
    const float index[1] = {static_cast<float>(task)};
    SetTaskObs(index);
  }
}

void Benchmark::DoReset(const ObsView& out) {
  Member(active_task_).Reset(ObsView{out.env_obs, member_task_obs_, out.pixels});
}

void Benchmark::DoStep(std::span<const float> action, const StepView& out) {
  Member(active_task_).Step(action, StepView{out.env_obs, member_task_obs_, out.reward,
                                                 out.terminated, out.truncated, out.info,
                                                 out.pixels});
}

namespace {

// Reads the true goal from the task it acts in and hands the task's scripted
// policy an observation with that goal, so it acts with the goal hidden too.
class PrivilegedScriptedPolicy : public Policy {
 public:
  using TaskOf = std::function<const SawyerTask*()>;
  PrivilegedScriptedPolicy(TaskOf task_of, const std::vector<std::string>& task_ids)
      : task_of_(std::move(task_of)) {
    for (const auto& id : task_ids) policies_.emplace(id, MakeScriptedPolicy(id));
  }
  void BeginEpisode() override {
    for (auto& [id, policy] : policies_) policy->BeginEpisode();
  }
  void Act(std::span<const float> env_obs, std::span<const float>,
           std::span<float> action) override {
    const SawyerTask* task = task_of_();
    if (task == nullptr) throw EpisodeStateError("scripted policy: the env has no task yet");
    std::copy(env_obs.begin(), env_obs.begin() + kObsSize, obs_);
    for (int i = 0; i < 3; ++i) obs_[kObsGoal + i] = static_cast<float>(task->state().goal[i]);
    policies_.at(task->id())->Act(obs_, {}, action);
  }

 private:
  TaskOf task_of_;
  std::unordered_map<std::string, std::unique_ptr<Policy>> policies_;
  float obs_[kObsSize] = {};
};

}  // namespace

std::unique_ptr<Policy> SawyerTask::CreateScriptedPolicy() const {
  return std::make_unique<PrivilegedScriptedPolicy>([this] { return this; },
                                                    std::vector<std::string>{id()});
}

std::unique_ptr<Policy> Benchmark::CreateScriptedPolicy() const {
  return std::make_unique<PrivilegedScriptedPolicy>(
      [this]() -> const SawyerTask* {
        return active_task_ < 0 ? nullptr : &Member(active_task_);
      },
      config_.tasks);
}

sim::Scene Benchmark::ActiveScene() const {
  return active_task_ < 0 ? sim::Scene{} : Member(active_task_).ActiveScene();
}

void Benchmark::SaveSceneXml(const std::string& path) const {
  if (active_task_ < 0) {
    throw EpisodeStateError("env '" + id() + "': SaveSceneXml needs a task; call SetTaskState "
                            "or ResetTaskState first");
  }
  Member(active_task_).SaveVariationXml(path);
}

const SawyerTask* ActiveSawyerTask(const Env& env) {
  if (const auto* bench = FindThroughWrappers<Benchmark>(env)) {
    return bench->active_task() < 0 ? nullptr : &bench->member(bench->active_task());
  }
  return FindThroughWrappers<SawyerTask>(env);
}

std::unique_ptr<Policy> MakeScriptedPolicyFor(const Env& env) {
  if (const auto* bench = FindThroughWrappers<Benchmark>(env)) return bench->CreateScriptedPolicy();
  if (const auto* task = FindThroughWrappers<SawyerTask>(env)) return task->CreateScriptedPolicy();
  throw ConfigError("no scripted policy for env '" + env.id() +
                    "': scripted policies exist for the manipulation tasks and benchmarks");
}

void RegisterBenchmarks(Registry& registry) {
  std::vector<std::string> task_ids = ManipulationTaskIds();
  const OptionSpec seed{"benchmark_seed", OptionType::kInt, 0,
                        "seed of the task variations (train split; test uses seed + 1)"};
  const OptionSpec variations{"num_variations", OptionType::kInt, 50,
                              "variations (object and goal positions) per task"};
  const OptionSpec one_hot{"task_id_in_obs", OptionType::kBool, false,
                           "append the one-hot task id to the observation (v3's use_one_hot; "
                           "the task observation has the id either way)"};
  const OptionSpec split{"split", OptionType::kString, "train", "which tasks / variations",
                         {"train", "test"}};
  const OptionSpec task{"task", OptionType::kString, "reach", "the task", task_ids};
  const OptionSpec reward{"reward_version", OptionType::kString, "v2",
                          "Meta-World's reward_function_version of every member: v2 or v1",
                          {"v2", "v1"}};

  auto make = [](BenchmarkConfig config, const Options& options) -> std::unique_ptr<Env> {
    config.seed = static_cast<uint64_t>(options.Int("benchmark_seed"));
    const int64_t variations = options.Int("num_variations");
    if (variations < 1 || variations > 100000) {
      throw ConfigError("benchmark '" + config.id + "': option 'num_variations' must be in [1, " +
                        "100000], got " + std::to_string(variations));
    }
    config.num_variations = static_cast<int>(variations);
    config.reward_version =
        options.String("reward_version") == "v1" ? RewardVersion::kV1 : RewardVersion::kV2;
    auto bench = std::make_unique<Benchmark>(std::move(config));
    if (bench->config().meta || !options.Bool("task_id_in_obs")) return bench;
    return std::make_unique<AppendTaskOneHot>(std::move(bench));
  };
  auto split_of = [](const Options& options) {
    return options.String("split") == "test" ? BenchmarkSplit::kTest : BenchmarkSplit::kTrain;
  };
  for (const BenchmarkSplits& b : PublishedBenchmarks()) {
    if (b.meta) {
      registry.Add({b.id, "benchmark", b.description, {seed, variations, split, reward},
                    [make, split_of, &b](const Options& options) {
                      const BenchmarkSplit s = split_of(options);
                      return make({b.id, s == BenchmarkSplit::kTrain ? b.train : b.test, true, s},
                                  options);
                    }});
    } else {
      registry.Add({b.id, "benchmark", b.description + ", task id as task observation",
                    {seed, variations, one_hot, reward},
                    [make, &b](const Options& options) {
                      return make({b.id, b.train, false, BenchmarkSplit::kTrain}, options);
                    }});
    }
  }
  registry.Add({"mt1", "benchmark", "MT1: one task x 50 variations, goal visible",
                {task, seed, variations, one_hot, reward},
                [make](const Options& options) {
                  return make({"mt1", {options.String("task")}, false, BenchmarkSplit::kTrain},
                              options);
                }});
  registry.Add({"ml1", "benchmark",
                "ML1: one task, 50 train variations and 50 different test variations, goal "
                "hidden",
                {task, seed, variations, split, reward},
                [make, split_of](const Options& options) {
                  return make({"ml1", {options.String("task")}, true, split_of(options)}, options);
                }});
}

}  // namespace manyworlds::manipulation
