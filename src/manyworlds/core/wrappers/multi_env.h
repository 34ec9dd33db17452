// MultiEnv: k different envs presented as one multi-task env whose task is
// the env index (MTEnv's MultiEnvWrapper, built eagerly).
//
// All envs must share the action space, the kind and shape of the
// env-observation space (Box bounds may differ: the combined space is their
// union) and the info fields (same names, same order); they may differ in
// task observation and episode limit. The agent sees the index only: task observation
// Discrete(k). Each env keeps its own episode limit; spec().max_episode_steps
// is the largest of them (0 if any env has none).
//
// Task state: {"env": <this id>, "params": {"index": i, "task": <env i's
// task state JSON>}}. Sampling picks i uniformly with the task generator,
// then a task of env i with env i's own task generator.
//
// Seed(s) / SeedTask(s) seed env i with MixSeed(s, i), so members differ.
//
// MultiEnv owns several envs, so it derives from Env rather than Wrapper
// (which forwards to a single inner env).
#ifndef MANYWORLDS_CORE_WRAPPERS_MULTI_ENV_H_
#define MANYWORLDS_CORE_WRAPPERS_MULTI_ENV_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "manyworlds/core/env.h"

namespace manyworlds {

class MultiEnv : public Env {
 public:
  // env_id: the combined env's id; empty gives "multi-env(<id 0>,<id 1>,...)".
  // Throws ConfigError if envs is empty, holds a null env, or two envs differ
  // in action space, env-observation space kind or shape, or info fields (the message names
  // the first mismatch).
  explicit MultiEnv(std::vector<std::unique_ptr<Env>> envs, std::string env_id = "");

  int num_envs() const { return static_cast<int>(envs_.size()); }
  Env& env(int index) { return *envs_.at(index); }
  const Env& env(int index) const { return *envs_.at(index); }
  // Index of the selected env; -1 before a task is set.
  int active_index() const { return active_; }

  void Seed(uint64_t seed) override;
  void SeedTask(uint64_t seed) override;
  void SetMaxEpisodeSteps(int64_t max_episode_steps) override;

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  std::vector<std::unique_ptr<Env>> envs_;
  // Scratch task observations, one per env (their sizes may differ).
  std::vector<std::vector<float>> member_task_obs_;
  int active_ = -1;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_MULTI_ENV_H_
