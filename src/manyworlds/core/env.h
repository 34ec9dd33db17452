// The multi-task environment interface.
//
// Semantics follow MTEnv (structured observation {env_obs, task_obs}, task
// state that can be sampled, read, set and serialized, separate env and task
// seeds) and Gymnasium's step (terminated vs truncated):
//
//   env->Seed(1);                  // dynamics and initial states
//   env->SeedTask(2);              // task sampling
//   env->ResetTaskState();         // = SetTaskState(SampleTaskState())
//   Observation obs = env->Reset();
//   StepResult r = env->Step(action);   // until r.terminated || r.truncated
//
// Reset() without a task set samples one with the task seed. Seeds default
// to 0, so an env is deterministic even if never seeded.
//
// Two call styles: Reset()/Step() return freshly allocated results; the
// view overloads write into caller-owned buffers and allocate nothing (the
// batched executor uses them).
#ifndef MANYWORLDS_CORE_ENV_H_
#define MANYWORLDS_CORE_ENV_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "manyworlds/core/rng.h"
#include "manyworlds/core/space.h"
#include "manyworlds/core/task_state.h"

namespace manyworlds {

struct EnvSpec {
  std::string id;
  std::string description;
  Space action_space;
  Space env_obs_space;
  Space task_obs_space;
  // Names of the float fields every step reports (e.g. "success").
  std::vector<std::string> info_fields;
  // Episodes are truncated after this many steps; 0 means no limit.
  int64_t max_episode_steps = 0;
  // Pixel observations (the registry option obs=pixels): a Box of shape
  // (channels, height, width) whose values are bytes in [0, 255], delivered
  // through the views' `pixels` spans (uint8, row-major, channels first).
  // Empty (flat_size() 0) for envs without them, which is every env unless a
  // pixel wrapper (sim/pixel_observation.h) is outside it. env_obs stays the
  // proprioceptive state: an asymmetric critic reads it beside the pixels.
  Space pixel_space;
  // False for envs whose dynamics and initial states are deterministic given
  // the task (point navigation, the Sawyer tasks): the env seed then has no
  // effect, and the env checker verifies exactly that instead.
  bool uses_env_seed = true;

  // Index of an info field, or -1 if the env does not report it.
  int InfoIndex(std::string_view name) const;
};

// A named group of task states, e.g. one benchmark task and its variations.
struct TaskGroup {
  std::string name;
  std::vector<TaskState> states;
};

struct Observation {
  std::vector<float> env_obs;
  std::vector<float> task_obs;
  std::vector<uint8_t> pixels;  // (pixel_space.flat_size()); empty without pixels
};

// Named float fields reported by a step.
struct Info {
  std::vector<std::string> names;
  std::vector<float> values;

  std::optional<float> Find(std::string_view name) const;
  // Throws Error if the field is absent.
  float Get(std::string_view name) const;
};

struct StepResult {
  Observation obs;
  float reward = 0.0f;
  bool terminated = false;  // the MDP reached a terminal state
  bool truncated = false;   // the episode was cut (time limit)
  Info info;
};

// Caller-owned output buffers for one observation.
struct ObsView {
  std::span<float> env_obs;   // (env_obs_space.flat_size())
  std::span<float> task_obs;  // (task_obs_space.flat_size())
  std::span<uint8_t> pixels;  // (pixel_space.flat_size()); empty without pixels
};

// Caller-owned output buffers for one step.
struct StepView {
  std::span<float> env_obs;   // (env_obs_space.flat_size())
  std::span<float> task_obs;  // (task_obs_space.flat_size())
  float* reward = nullptr;
  bool* terminated = nullptr;
  bool* truncated = nullptr;
  std::span<float> info;      // (info_fields.size())
  std::span<uint8_t> pixels;  // (pixel_space.flat_size()); empty without pixels
};

class Env {
 public:
  virtual ~Env() = default;
  Env(const Env&) = delete;
  Env& operator=(const Env&) = delete;

  const EnvSpec& spec() const { return spec_; }
  const std::string& id() const { return spec_.id; }

  // Seeds the env generator (dynamics, initial states). Takes effect at the
  // next Reset.
  virtual void Seed(uint64_t seed);
  // Seeds the task generator used by SampleTaskState.
  virtual void SeedTask(uint64_t seed);

  TaskState SampleTaskState();
  // Throws EpisodeStateError if no task has been set or sampled yet.
  TaskState GetTaskState() const;
  // Validates the state (TaskStateError if malformed or foreign) and switches
  // to that task. The running episode ends: call Reset next.
  void SetTaskState(const TaskState& state);
  void ResetTaskState() { SetTaskState(SampleTaskState()); }
  bool has_task() const { return has_task_; }
  // The task observation of the current task.
  std::span<const float> task_obs() const { return task_obs_; }

  Observation Reset();
  StepResult Step(std::span<const float> action);
  void Reset(const ObsView& out);
  void Step(std::span<const float> action, const StepView& out);

  // Changes the episode limit (0: none). The running episode ends.
  virtual void SetMaxEpisodeSteps(int64_t max_episode_steps);

  // The fixed task states an evaluation should cover, in groups (a
  // benchmark: one group per task holding its variations). Empty for envs
  // whose tasks come from a continuous distribution.
  virtual std::vector<TaskGroup> EvaluationTasks() const { return {}; }

  int64_t elapsed_steps() const { return elapsed_steps_; }
  // True before the first Reset, after SetTaskState, and once an episode
  // has terminated or been truncated.
  bool needs_reset() const { return phase_ != Phase::kRunning; }

 protected:
  explicit Env(EnvSpec spec);

  EnvSpec& mutable_spec() { return spec_; }
  Rng& env_rng() { return env_rng_; }
  Rng& task_rng() { return task_rng_; }
  // Sets the task observation; call from DoSetTaskState.
  void SetTaskObs(std::span<const float> task_obs);

  // Draws a task state from the task generator.
  virtual TaskState DoSampleTaskState(Rng& task_rng) = 0;
  virtual TaskState DoGetTaskState() const = 0;
  // Validates and applies; must call SetTaskObs.
  virtual void DoSetTaskState(const TaskState& state) = 0;
  // Starts an episode; writes out.env_obs (task_obs is filled by Env).
  virtual void DoReset(const ObsView& out) = 0;
  // Advances one step with a valid action (Box actions already clipped).
  // Writes env_obs, reward, terminated, info (and truncated if the env cuts
  // episodes itself). All outputs are zeroed before the call; task_obs and
  // the time limit are handled by Env.
  virtual void DoStep(std::span<const float> action, const StepView& out) = 0;

 private:
  enum class Phase { kNeedsReset, kRunning, kEnded };

  void ValidateAction(std::span<const float> action);
  void CheckView(size_t env_obs, size_t task_obs, size_t info, size_t pixels) const;

  EnvSpec spec_;
  Rng env_rng_{0};
  Rng task_rng_{0};
  std::vector<float> task_obs_;
  std::vector<float> clipped_action_;
  Phase phase_ = Phase::kNeedsReset;
  bool has_task_ = false;
  int64_t elapsed_steps_ = 0;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_ENV_H_
