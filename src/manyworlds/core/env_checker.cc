#include "manyworlds/core/env_checker.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <set>
#include <utility>

#include "manyworlds/core/error.h"
#include "manyworlds/core/hash.h"

namespace manyworlds {
namespace {

using MakeEnv = std::function<std::unique_ptr<Env>()>;

// Thrown by a check body to fail the check with a message.
class CheckFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void Fail(const std::string& message) { throw CheckFailed(message); }

std::string ErrorTypeName(const std::exception& e) {
  if (dynamic_cast<const TaskStateError*>(&e)) return "TaskStateError";
  if (dynamic_cast<const InvalidActionError*>(&e)) return "InvalidActionError";
  if (dynamic_cast<const EpisodeStateError*>(&e)) return "EpisodeStateError";
  if (dynamic_cast<const ConfigError*>(&e)) return "ConfigError";
  if (dynamic_cast<const Error*>(&e)) return "manyworlds::Error";
  return "std::exception";
}

template <typename E>
std::string ExpectedName();
template <>
std::string ExpectedName<TaskStateError>() {
  return "TaskStateError";
}
template <>
std::string ExpectedName<InvalidActionError>() {
  return "InvalidActionError";
}
template <>
std::string ExpectedName<EpisodeStateError>() {
  return "EpisodeStateError";
}

// Fails unless fn throws exactly an E (or a subclass).
template <typename E, typename Fn>
void ExpectThrows(const std::string& what, Fn&& fn) {
  try {
    fn();
  } catch (const E&) {
    return;
  } catch (const std::exception& e) {
    Fail(what + " threw " + ErrorTypeName(e) + " instead of " + ExpectedName<E>() + ": " +
         e.what());
  }
  Fail(what + " did not throw " + ExpectedName<E>());
}

std::string Values(std::span<const float> values) {
  std::string s = "[";
  for (size_t i = 0; i < values.size() && i < 8; ++i) {
    s += (i ? ", " : "") + std::to_string(values[i]);
  }
  if (values.size() > 8) s += ", ...";
  return s + "]";
}

bool AllFinite(std::span<const float> values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); });
}

// One Reset or Step, flattened: env_obs, task_obs, then (steps only) reward,
// terminated, truncated and info.
struct Record {
  int64_t step = -1;  // -1 for a Reset
  std::vector<float> values;
};

struct Trajectory {
  std::vector<Record> records;
  // First observation outside its space, first non-finite reward or info
  // value (empty if none).
  std::string obs_problem;
  std::string value_problem;
};

void NoteObs(const EnvSpec& spec, int64_t step, const Observation& obs, Trajectory& traj) {
  if (!traj.obs_problem.empty()) return;
  const std::string where = step < 0 ? "after a reset" : "at step " + std::to_string(step);
  if (!spec.env_obs_space.Contains(obs.env_obs) || !AllFinite(obs.env_obs)) {
    traj.obs_problem = "env_obs " + Values(obs.env_obs) + " " + where +
                       " is not a finite value of " + spec.env_obs_space.ToString();
  } else if (!spec.task_obs_space.Contains(obs.task_obs) || !AllFinite(obs.task_obs)) {
    traj.obs_problem = "task_obs " + Values(obs.task_obs) + " " + where +
                       " is not a finite value of " + spec.task_obs_space.ToString();
  }
}

// Pixel observations enter a record as a 64-bit FNV-1a digest in three exact
// floats of 22 bits each (the frames themselves would make trajectories huge).
void AppendPixelDigest(const std::vector<uint8_t>& pixels, std::vector<float>& values) {
  if (pixels.empty()) return;
  const uint64_t h = Fnv1a(pixels.data(), pixels.size());
  for (int k = 0; k < 3; ++k) values.push_back(static_cast<float>((h >> (22 * k)) & 0x3fffff));
}

void RecordReset(const EnvSpec& spec, const Observation& obs, Trajectory& traj) {
  Record r;
  r.values = obs.env_obs;
  r.values.insert(r.values.end(), obs.task_obs.begin(), obs.task_obs.end());
  AppendPixelDigest(obs.pixels, r.values);
  traj.records.push_back(std::move(r));
  NoteObs(spec, -1, obs, traj);
}

void RecordStep(const EnvSpec& spec, int64_t step, const StepResult& result, Trajectory& traj) {
  Record r;
  r.step = step;
  r.values = result.obs.env_obs;
  r.values.insert(r.values.end(), result.obs.task_obs.begin(), result.obs.task_obs.end());
  AppendPixelDigest(result.obs.pixels, r.values);
  r.values.push_back(result.reward);
  r.values.push_back(result.terminated ? 1.0f : 0.0f);
  r.values.push_back(result.truncated ? 1.0f : 0.0f);
  r.values.insert(r.values.end(), result.info.values.begin(), result.info.values.end());
  traj.records.push_back(std::move(r));
  NoteObs(spec, step, result.obs, traj);
  if (traj.value_problem.empty()) {
    if (!std::isfinite(result.reward)) {
      traj.value_problem = "reward " + std::to_string(result.reward) + " at step " +
                           std::to_string(step) + " is not finite";
    } else if (!AllFinite(result.info.values)) {
      traj.value_problem = "info " + Values(result.info.values) + " at step " +
                           std::to_string(step) + " has a non-finite value";
    }
  }
}

// Random actions from a generator of its own, so that two runs with the same
// env seeds see the same actions. Resets after every episode end unless
// first_episode_only.
Trajectory RunTrajectory(Env& env, uint64_t action_seed, int64_t steps, bool first_episode_only) {
  Trajectory traj;
  Rng action_rng(action_seed);
  const EnvSpec& spec = env.spec();
  RecordReset(spec, env.Reset(), traj);
  std::vector<float> action(spec.action_space.flat_size());
  for (int64_t step = 0; step < steps; ++step) {
    spec.action_space.Sample(action_rng, action);
    const StepResult result = env.Step(action);
    RecordStep(spec, step, result, traj);
    if (result.terminated || result.truncated) {
      if (first_episode_only) break;
      RecordReset(spec, env.Reset(), traj);
    }
  }
  return traj;
}

bool BitwiseEqual(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

// Empty if equal, else where they first differ.
std::string FirstDifference(const Trajectory& a, const Trajectory& b) {
  const size_t n = std::min(a.records.size(), b.records.size());
  for (size_t i = 0; i < n; ++i) {
    const Record& ra = a.records[i];
    const Record& rb = b.records[i];
    if (ra.step != rb.step || !BitwiseEqual(ra.values, rb.values)) {
      const std::string where = ra.step < 0 ? "reset before step " + std::to_string(rb.step + 1)
                                            : "step " + std::to_string(ra.step);
      return "first difference at " + where + " (record " + std::to_string(i) +
             "): " + Values(ra.values) + " vs " + Values(rb.values);
    }
  }
  if (a.records.size() != b.records.size()) {
    return "trajectories have " + std::to_string(a.records.size()) + " and " +
           std::to_string(b.records.size()) + " records";
  }
  return "";
}

std::string CheckSpace(const std::string& name, const Space& space) {
  if (space.is_discrete()) return space.n() >= 1 ? "" : name + " is Discrete with n < 1";
  const size_t size = static_cast<size_t>(space.flat_size());
  if (space.low().size() != size || space.high().size() != size) {
    return name + " " + space.ToString() + " has bounds of the wrong length";
  }
  for (size_t i = 0; i < size; ++i) {
    if (std::isnan(space.low()[i]) || std::isnan(space.high()[i]) ||
        space.low()[i] > space.high()[i]) {
      return name + " " + space.ToString() + " has invalid bounds at element " + std::to_string(i);
    }
  }
  return "";
}

class Checker {
 public:
  Checker(const MakeEnv& make_env, const CheckOptions& options)
      : make_env_(make_env), options_(options) {}

  CheckReport Run();

 private:
  void Check(const std::string& name, const std::function<std::string()>& body);
  std::unique_ptr<Env> Make();
  // A fresh instance seeded with (env_seed, task_seed).
  std::unique_ptr<Env> MakeSeeded(uint64_t env_seed, uint64_t task_seed);
  // Trajectory of a fresh instance with the option seeds (computed once).
  const Trajectory& Baseline();
  uint64_t action_seed() const { return MixSeed(options_.seed, 0xAC7104); }

  std::string SpacesWellFormed();
  std::string InfoFieldsUnique();
  std::string SameSeedsIdentical();
  std::string DifferentEnvSeedsDiffer();
  std::string DifferentTaskSeedsDiffer();
  std::string ObservationsInSpace();
  std::string RewardsAndInfoFinite();
  std::string TaskStateRoundTrip();
  std::string TaskStateReproducesTrajectory();
  std::string ForeignTaskStateRejected();
  std::string MalformedTaskStateRejected();
  std::string StepBeforeResetRaises();
  std::string StepAfterEndRaises();
  std::string WrongActionLengthRaises();
  std::string NonFiniteActionRaises();
  std::string DiscreteActionOutOfSpaceRaises();
  std::string BoxActionClipped();

  const MakeEnv& make_env_;
  CheckOptions options_;
  CheckReport report_;
  EnvSpec spec_;
  std::optional<Trajectory> baseline_;
};

void Checker::Check(const std::string& name, const std::function<std::string()>& body) {
  CheckResult result;
  result.name = name;
  try {
    result.message = body();
    result.passed = true;
  } catch (const CheckFailed& e) {
    result.message = e.what();
  } catch (const std::exception& e) {
    result.message = "unexpected " + ErrorTypeName(e) + ": " + e.what();
  } catch (...) {
    result.message = "unexpected exception of a non-standard type";
  }
  report_.checks.push_back(std::move(result));
}

std::unique_ptr<Env> Checker::Make() {
  std::unique_ptr<Env> env = make_env_();
  if (!env) Fail("the factory returned a null env");
  return env;
}

std::unique_ptr<Env> Checker::MakeSeeded(uint64_t env_seed, uint64_t task_seed) {
  std::unique_ptr<Env> env = Make();
  env->Seed(env_seed);
  env->SeedTask(task_seed);
  return env;
}

const Trajectory& Checker::Baseline() {
  if (!baseline_) {
    auto env = MakeSeeded(options_.seed, options_.task_seed);
    baseline_ = RunTrajectory(*env, action_seed(), options_.steps, false);
  }
  return *baseline_;
}

CheckReport Checker::Run() {
  bool made = false;
  Check("make-env", [&] {
    auto env = Make();
    spec_ = env->spec();
    report_.env_id = spec_.id;
    made = true;
    return "made '" + spec_.id + "'";
  });
  if (!made) return report_;
  Check("spaces-well-formed", [&] { return SpacesWellFormed(); });
  Check("info-fields-unique", [&] { return InfoFieldsUnique(); });
  Check("same-seeds-identical-trajectories", [&] { return SameSeedsIdentical(); });
  Check("different-env-seeds-differ", [&] { return DifferentEnvSeedsDiffer(); });
  Check("different-task-seeds-differ", [&] { return DifferentTaskSeedsDiffer(); });
  Check("observations-in-space", [&] { return ObservationsInSpace(); });
  Check("rewards-and-info-finite", [&] { return RewardsAndInfoFinite(); });
  Check("task-state-round-trip", [&] { return TaskStateRoundTrip(); });
  Check("task-state-reproduces-trajectory", [&] { return TaskStateReproducesTrajectory(); });
  Check("foreign-task-state-rejected", [&] { return ForeignTaskStateRejected(); });
  Check("malformed-task-state-rejected", [&] { return MalformedTaskStateRejected(); });
  Check("step-before-reset-raises", [&] { return StepBeforeResetRaises(); });
  Check("step-after-end-raises", [&] { return StepAfterEndRaises(); });
  Check("wrong-action-length-raises", [&] { return WrongActionLengthRaises(); });
  Check("non-finite-action-raises", [&] { return NonFiniteActionRaises(); });
  Check("discrete-action-out-of-space-raises", [&] { return DiscreteActionOutOfSpaceRaises(); });
  Check("box-action-clipped", [&] { return BoxActionClipped(); });
  return report_;
}

std::string Checker::SpacesWellFormed() {
  if (spec_.id.empty()) Fail("the env id is empty");
  const std::pair<const char*, const Space*> spaces[] = {
      {"action space", &spec_.action_space},
      {"env observation space", &spec_.env_obs_space},
      {"task observation space", &spec_.task_obs_space}};
  for (const auto& [name, space] : spaces) {
    const std::string problem = CheckSpace(name, *space);
    if (!problem.empty()) Fail(problem);
  }
  if (spec_.action_space.flat_size() < 1) {
    Fail("action space " + spec_.action_space.ToString() + " is empty");
  }
  if (spec_.max_episode_steps < 0) {
    Fail("max_episode_steps is " + std::to_string(spec_.max_episode_steps) + " (must be >= 0)");
  }
  return "action " + spec_.action_space.ToString() + ", env_obs " + spec_.env_obs_space.ToString() +
         ", task_obs " + spec_.task_obs_space.ToString();
}

std::string Checker::InfoFieldsUnique() {
  std::set<std::string> seen;
  for (const auto& field : spec_.info_fields) {
    if (field.empty()) Fail("an info field has an empty name");
    if (!seen.insert(field).second) Fail("info field '" + field + "' appears twice");
  }
  return std::to_string(spec_.info_fields.size()) + " info fields";
}

std::string Checker::SameSeedsIdentical() {
  const Trajectory& a = Baseline();
  auto env = MakeSeeded(options_.seed, options_.task_seed);
  const Trajectory b = RunTrajectory(*env, action_seed(), options_.steps, false);
  const std::string diff = FirstDifference(a, b);
  if (!diff.empty()) {
    Fail("two instances with env seed " + std::to_string(options_.seed) + " and task seed " +
         std::to_string(options_.task_seed) + " differ (hidden state or unseeded randomness?); " +
         diff);
  }
  return std::to_string(a.records.size()) + " records identical";
}

std::string Checker::DifferentEnvSeedsDiffer() {
  const Trajectory& a = Baseline();
  auto env = MakeSeeded(options_.seed + 1, options_.task_seed);
  const Trajectory b = RunTrajectory(*env, action_seed(), options_.steps, false);
  if (!spec_.uses_env_seed) {
    // Declared deterministic: a difference means hidden randomness.
    const std::string diff = FirstDifference(a, b);
    if (!diff.empty()) {
      Fail("the env declares uses_env_seed = false, but env seeds " +
           std::to_string(options_.seed) + " and " + std::to_string(options_.seed + 1) +
           " give different trajectories: " + diff);
    }
    return "env seed has no effect, as declared (uses_env_seed = false)";
  }
  if (FirstDifference(a, b).empty()) {
    Fail("env seeds " + std::to_string(options_.seed) + " and " +
         std::to_string(options_.seed + 1) + " give identical trajectories: Seed has no effect");
  }
  return "trajectories differ";
}

std::string Checker::DifferentTaskSeedsDiffer() {
  const Trajectory& a = Baseline();
  auto env = MakeSeeded(options_.seed, options_.task_seed + 1);
  const Trajectory b = RunTrajectory(*env, action_seed(), options_.steps, false);
  if (!FirstDifference(a, b).empty()) return "trajectories differ";
  // Identical trajectories are fine for an env with a single task.
  std::vector<TaskState> drawn;
  for (uint64_t task_seed : {options_.task_seed, options_.task_seed + 1}) {
    auto sampler = MakeSeeded(options_.seed, task_seed);
    for (int i = 0; i < 8; ++i) drawn.push_back(sampler->SampleTaskState());
  }
  const bool single_task =
      std::all_of(drawn.begin(), drawn.end(), [&](const TaskState& s) { return s == drawn[0]; });
  if (single_task) return "not applicable: the env samples a single task";
  Fail("task seeds " + std::to_string(options_.task_seed) + " and " +
       std::to_string(options_.task_seed + 1) +
       " give identical trajectories although the env has several tasks: SeedTask has no effect");
}

std::string Checker::ObservationsInSpace() {
  const Trajectory& a = Baseline();
  if (!a.obs_problem.empty()) Fail(a.obs_problem);
  return std::to_string(a.records.size()) + " observations inside their spaces";
}

std::string Checker::RewardsAndInfoFinite() {
  const Trajectory& a = Baseline();
  if (!a.value_problem.empty()) Fail(a.value_problem);
  return "all finite";
}

std::string Checker::TaskStateRoundTrip() {
  auto env = MakeSeeded(options_.seed, options_.task_seed);
  for (int i = 0; i < 4; ++i) {
    const TaskState sampled = env->SampleTaskState();
    const std::string text = sampled.Dump();
    const TaskState parsed = TaskState::Parse(text);
    if (!(parsed == sampled) || parsed.Dump() != text) {
      Fail("sampled task state " + text + " does not survive Dump/Parse (got " + parsed.Dump() +
           ")");
    }
    env->SetTaskState(parsed);
    const TaskState got = env->GetTaskState();
    if (!(got == sampled)) {
      Fail("SetTaskState(" + text + ") then GetTaskState() gives " + got.Dump());
    }
    // Another instance, given the text, must report the same state.
    auto other = MakeSeeded(options_.seed + 1, options_.task_seed + 1);
    other->SetTaskState(TaskState::Parse(got.Dump()));
    const TaskState other_got = other->GetTaskState();
    if (!(other_got == sampled)) {
      Fail("another instance given " + text + " reports task state " + other_got.Dump());
    }
    if (!BitwiseEqual(std::vector<float>(env->task_obs().begin(), env->task_obs().end()),
                      std::vector<float>(other->task_obs().begin(), other->task_obs().end()))) {
      Fail("two instances given task state " + text + " have task observations " +
           Values(env->task_obs()) + " and " + Values(other->task_obs()));
    }
  }
  return "4 sampled states round-trip";
}

std::string Checker::TaskStateReproducesTrajectory() {
  auto a = MakeSeeded(options_.seed, options_.task_seed);
  a->ResetTaskState();
  const std::string text = a->GetTaskState().Dump();
  const Trajectory ta = RunTrajectory(*a, action_seed(), options_.steps, true);
  // The other instance has another task seed and a task of its own first, so
  // only the state's content can make the trajectories equal.
  auto b = MakeSeeded(options_.seed, options_.task_seed + 1);
  b->ResetTaskState();
  b->SetTaskState(TaskState::Parse(text));
  const Trajectory tb = RunTrajectory(*b, action_seed(), options_.steps, true);
  const std::string diff = FirstDifference(ta, tb);
  if (!diff.empty()) {
    Fail("task state " + text.substr(0, 200) +
         " set on another instance gives another first episode; " + diff);
  }
  return "first episode (" + std::to_string(ta.records.size() - 1) + " steps) reproduced";
}

std::string Checker::ForeignTaskStateRejected() {
  auto env = MakeSeeded(options_.seed, options_.task_seed);
  TaskState foreign = env->SampleTaskState();
  foreign.env += "-foreign";
  ExpectThrows<TaskStateError>("SetTaskState with env '" + foreign.env + "'",
                               [&] { env->SetTaskState(foreign); });
  return "rejected";
}

std::string Checker::MalformedTaskStateRejected() {
  auto env = MakeSeeded(options_.seed, options_.task_seed);
  const TaskState valid = env->SampleTaskState();
  for (const nlohmann::json& params :
       {nlohmann::json::array({1, 2}), nlohmann::json(3.5), nlohmann::json("task")}) {
    TaskState bad{valid.env, params};
    ExpectThrows<TaskStateError>("SetTaskState with params " + params.dump(),
                                 [&] { env->SetTaskState(bad); });
  }
  if (!valid.params.is_object() || valid.params.empty()) {
    return "rejected params that are not an object (no fields to remove)";
  }
  for (const auto& [key, value] : valid.params.items()) {
    TaskState missing = valid;
    missing.params.erase(key);
    ExpectThrows<TaskStateError>("SetTaskState without field '" + key + "'",
                                 [&] { env->SetTaskState(missing); });
  }
  return "rejected params that are not an object and params missing a field";
}

std::string Checker::StepBeforeResetRaises() {
  auto env = MakeSeeded(options_.seed, options_.task_seed);
  Rng rng(action_seed());
  const std::vector<float> action = spec_.action_space.Sample(rng);
  ExpectThrows<EpisodeStateError>("Step on a new instance", [&] { env->Step(action); });
  env->Reset();
  env->ResetTaskState();
  ExpectThrows<EpisodeStateError>("Step after SetTaskState", [&] { env->Step(action); });
  return "raised EpisodeStateError";
}

std::string Checker::StepAfterEndRaises() {
  auto env = MakeSeeded(options_.seed, options_.task_seed);
  constexpr int64_t kLimit = 3;
  env->SetMaxEpisodeSteps(kLimit);
  Rng rng(action_seed());
  std::vector<float> action(spec_.action_space.flat_size());
  env->Reset();
  bool ended = false;
  for (int64_t step = 0; step < kLimit && !ended; ++step) {
    spec_.action_space.Sample(rng, action);
    const StepResult r = env->Step(action);
    ended = r.terminated || r.truncated;
  }
  if (!ended) Fail("SetMaxEpisodeSteps(3) did not end the episode after 3 steps");
  ExpectThrows<EpisodeStateError>("Step after the episode ended", [&] { env->Step(action); });
  env->Reset();
  env->Step(action);  // usable again after Reset
  return "raised EpisodeStateError; Reset recovers";
}

std::string Checker::WrongActionLengthRaises() {
  auto env = MakeSeeded(options_.seed, options_.task_seed);
  env->Reset();
  const size_t size = static_cast<size_t>(spec_.action_space.flat_size());
  Rng rng(action_seed());
  std::vector<float> valid = spec_.action_space.Sample(rng);
  std::vector<float> longer = valid;
  longer.push_back(valid.empty() ? 0.0f : valid[0]);
  ExpectThrows<InvalidActionError>("Step with " + std::to_string(size + 1) + " action values",
                                   [&] { env->Step(longer); });
  if (size > 0) {
    const std::vector<float> shorter(valid.begin(), valid.end() - 1);
    ExpectThrows<InvalidActionError>("Step with " + std::to_string(size - 1) + " action values",
                                     [&] { env->Step(shorter); });
  }
  env->Step(valid);  // a rejected action leaves the episode running
  return "raised InvalidActionError";
}

std::string Checker::NonFiniteActionRaises() {
  auto env = MakeSeeded(options_.seed, options_.task_seed);
  env->Reset();
  Rng rng(action_seed());
  const std::vector<float> valid = spec_.action_space.Sample(rng);
  if (valid.empty()) return "not applicable: empty action space";
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity()}) {
    std::vector<float> action = valid;
    action.back() = bad;
    ExpectThrows<InvalidActionError>("Step with action " + Values(action),
                                     [&] { env->Step(action); });
  }
  return "raised InvalidActionError for NaN and +-inf";
}

std::string Checker::DiscreteActionOutOfSpaceRaises() {
  if (!spec_.action_space.is_discrete()) return "not applicable: Box action space";
  auto env = MakeSeeded(options_.seed, options_.task_seed);
  env->Reset();
  const float n = static_cast<float>(spec_.action_space.n());
  for (float bad : {-1.0f, n, n + 1.0f, 0.5f}) {
    const std::vector<float> action{bad};
    ExpectThrows<InvalidActionError>("Step with discrete action " + std::to_string(bad),
                                     [&] { env->Step(action); });
  }
  return "raised InvalidActionError for -1, n, n+1 and 0.5";
}

std::string Checker::BoxActionClipped() {
  const Space& space = spec_.action_space;
  if (!space.is_box()) return "not applicable: Discrete action space";
  bool any_bounded = false;
  for (int64_t i = 0; i < space.flat_size(); ++i) {
    any_bounded = any_bounded || std::isfinite(space.low()[i]) || std::isfinite(space.high()[i]);
  }
  if (!any_bounded) return "not applicable: unbounded action space";
  // Twins with equal seeds: one gets actions beyond the bounds, the other the
  // clipped actions; everything they report must match bitwise.
  auto outside_env = MakeSeeded(options_.seed, options_.task_seed);
  auto clipped_env = MakeSeeded(options_.seed, options_.task_seed);
  Trajectory outside_traj, clipped_traj;
  RecordReset(spec_, outside_env->Reset(), outside_traj);
  RecordReset(spec_, clipped_env->Reset(), clipped_traj);
  Rng rng(action_seed());
  std::vector<float> outside(space.flat_size()), clipped(space.flat_size());
  const int64_t steps = std::min<int64_t>(options_.steps, 50);
  for (int64_t step = 0; step < steps; ++step) {
    space.Sample(rng, outside);
    for (int64_t i = 0; i < space.flat_size(); ++i) {
      const float low = space.low()[i], high = space.high()[i];
      const float width = std::isfinite(high - low) ? high - low : 1.0f;
      // Alternate sides so both bounds are exercised.
      const bool above = (step + i) % 2 == 0;
      if (above && std::isfinite(high)) {
        outside[i] = high + 0.5f + width;
      } else if (std::isfinite(low)) {
        outside[i] = low - 0.5f - width;
      } else if (std::isfinite(high)) {
        outside[i] = high + 0.5f + width;
      }
    }
    clipped = outside;
    space.Clip(clipped);
    const StepResult a = outside_env->Step(outside);
    const StepResult b = clipped_env->Step(clipped);
    RecordStep(spec_, step, a, outside_traj);
    RecordStep(spec_, step, b, clipped_traj);
    if (a.terminated || a.truncated) break;
  }
  const std::string diff = FirstDifference(outside_traj, clipped_traj);
  if (!diff.empty()) Fail("an action beyond the bounds acts unlike the clipped action; " + diff);
  return std::to_string(outside_traj.records.size() - 1) + " steps beyond the bounds match";
}

}  // namespace

bool CheckReport::ok() const {
  return std::all_of(checks.begin(), checks.end(), [](const CheckResult& c) { return c.passed; });
}

std::string CheckReport::ToString() const {
  std::string out;
  for (const auto& c : checks) {
    out += (c.passed ? "[PASS] " : "[FAIL] ") + c.name + ": " + c.message + "\n";
  }
  return out;
}

nlohmann::json CheckReport::ToJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : checks) {
    list.push_back({{"name", c.name}, {"passed", c.passed}, {"message", c.message}});
  }
  return {{"env_id", env_id}, {"ok", ok()}, {"checks", std::move(list)}};
}

CheckReport CheckEnv(const std::function<std::unique_ptr<Env>()>& make_env,
                     const CheckOptions& options) {
  Checker checker(make_env, options);
  return checker.Run();
}

}  // namespace manyworlds
