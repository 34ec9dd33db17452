// BatchedExecutor: steps N environments (any mix of tasks with the same
// action, env-observation and task-observation sizes and info fields) on T
// worker threads into preallocated contiguous buffers, in the spirit of
// EnvPool.
//
//   BatchedExecutor exec(std::move(envs), {.num_threads = 2});
//   exec.Seed(1, 2);
//   exec.Reset();
//   exec.Step(actions);           // actions: (num_envs x action_size)
//   use exec.env_obs(), exec.rewards(), ...
//
// or asynchronously: exec.Send(actions); ...other work...; exec.Recv();
//
// Auto-reset (on by default): when an env's episode ends in a step, the rows
// of rewards/terminated/truncated/info describe that last step, final_env_obs
// / final_task_obs hold its last observation, and env_obs / task_obs already
// hold the first observation of the next episode.
//
// Results never depend on num_threads: every env is stepped by exactly one
// thread per step and owns its random generators (seeded from (seed, index)).
// Errors thrown by an env are rethrown by Step/Recv (the lowest env index
// first); the executor stays usable after Reset.
#ifndef MANYWORLDS_CORE_EXECUTOR_H_
#define MANYWORLDS_CORE_EXECUTOR_H_

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "manyworlds/core/env.h"

namespace manyworlds {

struct ExecutorOptions {
  int num_threads = 1;     // >= 1; 1 steps on the calling thread (sync mode)
  bool auto_reset = true;
};

class BatchedExecutor {
 public:
  // Throws ConfigError if envs is empty, an env is null, sizes or info fields
  // differ between envs, or num_threads < 1.
  BatchedExecutor(std::vector<std::unique_ptr<Env>> envs, ExecutorOptions options = {});
  ~BatchedExecutor();
  BatchedExecutor(const BatchedExecutor&) = delete;
  BatchedExecutor& operator=(const BatchedExecutor&) = delete;

  int num_envs() const;
  int num_threads() const;
  int64_t action_size() const;
  int64_t env_obs_size() const;
  int64_t task_obs_size() const;
  // Bytes of one env's pixel observation (EnvSpec::pixel_space); 0 without pixels.
  int64_t pixels_size() const;
  const std::vector<std::string>& info_fields() const;
  Env& env(int index);

  // Env i gets Seed(MixSeed(env_seed, i)) and SeedTask(MixSeed(task_seed, i)).
  void Seed(uint64_t env_seed, uint64_t task_seed);
  // Switches env i to a task and resets it at once (its obs rows change).
  void SetTaskState(int index, const TaskState& state);
  // Resets every env and fills env_obs / task_obs.
  void Reset();
  // Resets env i alone, on its task, its random streams going on (its obs
  // rows change): an episode a caller ends early.
  void ResetEnv(int index);
  // Steps every env with its row of actions (num_envs x action_size).
  void Step(std::span<const float> actions);
  // Asynchronous step: Send copies the actions and returns at once; Recv
  // waits for the step to finish. Send twice without Recv is an error.
  void Send(std::span<const float> actions);
  void Recv();

  // Buffers, valid after Reset / Step / Recv until the next call.
  std::span<const float> env_obs() const;        // (num_envs x env_obs_size)
  std::span<const float> task_obs() const;       // (num_envs x task_obs_size)
  std::span<const float> rewards() const;        // (num_envs)
  std::span<const bool> terminated() const;      // (num_envs)
  std::span<const bool> truncated() const;       // (num_envs)
  std::span<const float> info() const;           // (num_envs x info_fields.size())
  std::span<const float> final_env_obs() const;  // (num_envs x env_obs_size), rows of ended envs
  std::span<const float> final_task_obs() const; // (num_envs x task_obs_size), rows of ended envs
  std::span<const int64_t> episode_steps() const;  // (num_envs) steps into the current episode
  // Pixel observations (empty unless the envs have a pixel_space), as env_obs / final_env_obs.
  std::span<const uint8_t> pixels() const;        // (num_envs x pixels_size)
  std::span<const uint8_t> final_pixels() const;  // (num_envs x pixels_size), rows of ended envs

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_EXECUTOR_H_
