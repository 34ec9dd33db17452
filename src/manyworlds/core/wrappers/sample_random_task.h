// SampleRandomTask: every episode runs on a freshly sampled task.
//
// Reset first draws a task with SampleTaskState (the inner env's sampler and
// the task seed) and then resets the inner env. One exception keeps
// SetTaskState meaningful: a task set explicitly (SetTaskState or
// ResetTaskState) is used for the next episode, and sampling resumes at the
// Reset after that. So evaluation code that sets a task gets that task, and
// a task state replays on another instance.
//
// Task states and the task observation are the inner env's.
#ifndef MANYWORLDS_CORE_WRAPPERS_SAMPLE_RANDOM_TASK_H_
#define MANYWORLDS_CORE_WRAPPERS_SAMPLE_RANDOM_TASK_H_

#include <memory>

#include "manyworlds/core/wrapper.h"

namespace manyworlds {

class SampleRandomTask : public Wrapper {
 public:
  explicit SampleRandomTask(std::unique_ptr<Env> inner);

 protected:
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;

 private:
  // True from an explicit SetTaskState until the next Reset.
  bool keep_task_ = false;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_SAMPLE_RANDOM_TASK_H_
