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

// The first env from `env` inward, through wrappers, that is a `T`: an env
// class, or a capability an env implements besides Env (ScriptedPolicySource,
// sim::SceneSource). Null if there is none. The one walk through wrappers, so
// that callers need no casts of their own.
template <typename T>
const T* FindThroughWrappers(const Env& env) {
  for (const Env* e = &env;;) {
    if (const auto* found = dynamic_cast<const T*>(e)) return found;
    const auto* wrapper = dynamic_cast<const Wrapper*>(e);
    if (wrapper == nullptr) return nullptr;
    e = &wrapper->inner();
  }
}

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPER_H_
