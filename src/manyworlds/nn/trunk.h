// The network inside a policy or a critic: a flat-buffer module that maps
// an input and the task of each row to outputs. Plain MLPs ignore the task
// (the one-hot, if any, is already in the input); the multi-task
// architectures (Soft Modularization, PaCo, MOORE: task_trunks.h) use it to
// route, compose or mix. GaussianPolicy and TwinCritic hold one, so SAC runs
// every architecture through the same update.
#ifndef MANYWORLDS_NN_TRUNK_H_
#define MANYWORLDS_NN_TRUNK_H_

#include <functional>
#include <memory>
#include <string>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"

namespace manyworlds::nn {

class TrunkImpl : public FlatModule {
 public:
  // x (B, input) and task (B) int64 in [0, num_tasks) -> (B, output), or
  // (E, B, output) for an ensemble of E members (twin critics: E = 2). A
  // trunk that ignores the task accepts an undefined one. params: the
  // layout order of params() (or detached_params(), or replicas).
  virtual torch::Tensor Forward(const torch::Tensor& x, const torch::Tensor& task,
                                at::ArrayRef<torch::Tensor> params) const = 0;
  // Whether Forward reads the task.
  virtual bool uses_task() const { return false; }

 protected:
  explicit TrunkImpl(std::string name) : FlatModule(std::move(name)) {}
};

// Builds a trunk of a fixed layout, drawing its initial values from the
// generator; the critic calls it twice (online and target).
using TrunkFactory =
    std::function<std::shared_ptr<TrunkImpl>(c10::optional<at::Generator> generator)>;

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_TRUNK_H_
