#include "manyworlds/core/wrappers/ntasks_id.h"

#include <algorithm>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds {
namespace {

std::string WrapperName(int n, TaskIdEncoding encoding) {
  return "ntasks-id(" + std::to_string(n) +
         (encoding == TaskIdEncoding::kOneHot ? ",one-hot" : "") + ")";
}

}  // namespace

NTasksId::NTasksId(std::unique_ptr<Env> inner, int n, TaskIdEncoding encoding)
    : NTasks(std::move(inner), n, WrapperName(n, encoding)), encoding_(encoding) {
  mutable_spec().task_obs_space =
      encoding == TaskIdEncoding::kIndex ? Space::Discrete(n) : Space::Box(0.0f, 1.0f, {n});
  id_obs_.assign(mutable_spec().task_obs_space.flat_size(), 0.0f);
}

TaskState NTasksId::DoSampleTaskState(Rng& task_rng) {
  const int index = SampleIndex(task_rng);
  return MakeIndexedTaskState(id(), index, tasks()[index]);
}

TaskState NTasksId::DoGetTaskState() const {
  return MakeIndexedTaskState(id(), index_, inner().GetTaskState());
}

void NTasksId::DoSetTaskState(const TaskState& state) {
  const auto [index, inner_state] = ReadIndexedTaskState(state, id(), n());
  try {
    inner().SetTaskState(inner_state);
  } catch (const TaskStateError& e) {
    throw IndexedTaskRejected(id(), "env '" + inner().id() + "'", e);
  }
  index_ = index;
  if (encoding_ == TaskIdEncoding::kIndex) {
    id_obs_[0] = static_cast<float>(index);
  } else {
    std::fill(id_obs_.begin(), id_obs_.end(), 0.0f);
    id_obs_[index] = 1.0f;
  }
  SetTaskObs(id_obs_);
}

void NTasksId::DoReset(const ObsView& out) {
  Wrapper::DoReset(out);
  // The base may mirror the inner task observation when the spaces happen to
  // be equal (n = 1, one-hot); the id is what the agent must see.
  SetTaskObs(id_obs_);
}

}  // namespace manyworlds
