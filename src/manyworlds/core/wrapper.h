// Base class of wrappers: an Env that owns another Env and forwards to it.
//
// A derived wrapper overrides only what it changes. The spec starts as a copy
// of the inner env's spec (the id gains a suffix) and may be edited in the
// derived constructor through mutable_spec().
#ifndef MANYWORLDS_CORE_WRAPPER_H_
#define MANYWORLDS_CORE_WRAPPER_H_

#include <memory>
#include <vector>

#include "manyworlds/core/env.h"

namespace manyworlds {

class Wrapper : public Env {
 public:
  // Throws Error if inner is null.
  Wrapper(std::unique_ptr<Env> inner, std::string_view name);

  Env& inner() { return *inner_; }
  const Env& inner() const { return *inner_; }

  void Seed(uint64_t seed) override;
  void SeedTask(uint64_t seed) override;
  void SetMaxEpisodeSteps(int64_t max_episode_steps) override;
  // The inner env's: wrappers pass task states through unchanged.
  std::vector<TaskGroup> EvaluationTasks() const override { return inner_->EvaluationTasks(); }

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  // Sets the inner task and mirrors its task observation.
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

  // Scratch buffer for the inner env's task observation (wrappers may change
  // the task observation's size).
  std::span<float> inner_task_obs() { return inner_task_obs_; }

 private:
  std::unique_ptr<Env> inner_;
  std::vector<float> inner_task_obs_;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPER_H_
