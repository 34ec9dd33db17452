#include "manyworlds/core/wrappers/sample_random_task.h"

namespace manyworlds {

SampleRandomTask::SampleRandomTask(std::unique_ptr<Env> inner)
    : Wrapper(std::move(inner), "sample-random-task") {}

void SampleRandomTask::DoSetTaskState(const TaskState& state) {
  Wrapper::DoSetTaskState(state);
  keep_task_ = true;
}

void SampleRandomTask::DoReset(const ObsView& out) {
  // Bypasses our DoSetTaskState so that the sampled task is not kept.
  if (!keep_task_) Wrapper::DoSetTaskState(SampleTaskState());
  keep_task_ = false;
  Wrapper::DoReset(out);
}

}  // namespace manyworlds
