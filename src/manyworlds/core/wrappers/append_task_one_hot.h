// AppendTaskOneHot: appends the one-hot task id to the env observation, for
// agents that take one flat vector.
//
// Needs a Discrete(n) task observation (NTasksId with kIndex, MultiEnv) and a
// Box env observation of m values (any shape). The env observation becomes
// Box((m + n,)) = [flattened env_obs, one_hot(task id)], with the inner
// bounds followed by [0, 1] for each one-hot element. The task observation
// is unchanged.
//
//   auto env = std::make_unique<AppendTaskOneHot>(
//       std::make_unique<SampleRandomTask>(std::make_unique<MultiEnv>(...)));
#ifndef MANYWORLDS_CORE_WRAPPERS_APPEND_TASK_ONE_HOT_H_
#define MANYWORLDS_CORE_WRAPPERS_APPEND_TASK_ONE_HOT_H_

#include <cstdint>
#include <memory>
#include <span>

#include "manyworlds/core/wrapper.h"

namespace manyworlds {

class AppendTaskOneHot : public Wrapper {
 public:
  // Throws ConfigError if the task observation is not Discrete or the env
  // observation is not a Box.
  explicit AppendTaskOneHot(std::unique_ptr<Env> inner);

  // Number of env observation values before the one-hot part.
  int64_t inner_obs_size() const { return inner_obs_size_; }
  int64_t num_tasks() const { return num_tasks_; }

 protected:
  void DoReset(const ObsView& out) override;
  void DoStep(std::span<const float> action, const StepView& out) override;

 private:
  void WriteOneHot(std::span<float> env_obs);

  int64_t inner_obs_size_;
  int64_t num_tasks_;
};

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_WRAPPERS_APPEND_TASK_ONE_HOT_H_
