// NTasksId: a fixed set of n tasks (as NTasks) whose index the agent sees.
//
// Task observation: Discrete(n) holding the index (kIndex, as MTEnv does),
// or Box(0, 1, (n,)) holding its one-hot vector (kOneHot).
//
// Task state (self-contained, so it runs on another instance or process even
// if that one drew a different task set):
//   {"env": <this wrapper's id>,
//    "params": {"index": <int in [0, n)>, "task": <inner task state JSON>}}
// SetTaskState checks the index range and lets the inner env validate the
// embedded state; it does not require that state to be in this instance's
// set.
#ifndef MANYWORLDS_CORE_WRAPPERS_NTASKS_ID_H_
#define MANYWORLDS_CORE_WRAPPERS_NTASKS_ID_H_

#include <memory>
#include <vector>

#include "manyworlds/core/wrappers/ntasks.h"

namespace manyworlds {

enum class TaskIdEncoding { kIndex, kOneHot };

class NTasksId : public NTasks {
 public:
  // Throws ConfigError if n < 1.
  NTasksId(std::unique_ptr<Env> inner, int n, TaskIdEncoding encoding = TaskIdEncoding::kIndex);

  TaskIdEncoding encoding() const { return encoding_; }
  // Index of the current task; -1 before one is set.
  int task_index() const { return index_; }
  // None: this wrapper's task states embed the inner ones in its own format.
  std::vector<TaskGroup> EvaluationTasks() const override { return {}; }

 protected:
  TaskState DoSampleTaskState(Rng& task_rng) override;
  TaskState DoGetTaskState() const override;
  void DoSetTaskState(const TaskState& state) override;
  void DoReset(const ObsView& out) override;

 private:
  TaskIdEncoding encoding_;
  int index_ = -1;
  std::vector<float> id_obs_;  // the task observation of index_
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_NTASKS_ID_H_
