// PaCo, parameter-compositional multi-task networks (Sun, Zhang, Xu,
// Tomizuka, NeurIPS 2022), as the authors' MT10 configuration builds them
// (TToTMooN/paco-mtrl, paco/examples/metaworld_mt10_paco_conf.py, and ALF's
// compositional layers, read as reference):
//   every linear map holds K = num_param_sets parameter sets (W_k, b_k);
//   a task's weights w(task) (K numbers, a bias-free linear map of the
//   one-hot task, unconstrained: `last_activation = identity`) combine
//   their pre-activations, y = sum_k w_k (x W_k + b_k), which is the layer
//   with parameters sum_k w_k (W_k, b_k);
//   num_layers hidden layers of width hidden_dim, ReLU, linear output;
//   the K sets start identical (`use_identical_init`), the task weights
//   differ, so the tasks' networks start as differently scaled copies.
// When a batch holds equally many rows of each task present (balanced
// replay batches, one env per task) each task's parameters are composed first
// and the layer is one product, as costly as a plain layer; otherwise the K
// products of a layer are one product with the sets side by side in its
// output dimension, combined per row (K times the cost). Each member (actor,
// each critic) has its own task weights. What PaCo's trainer adds (masking
// and resetting the task weights of tasks whose loss explodes) is in the SAC
// learner (sac.h).
// Differences: the task weights are drawn from N(0, 1 / num_tasks) (ALF's
// fan-in variance scaling of that layer, untruncated) and have no bias;
// the shared sets are orthogonal with zero biases, as our other MLPs.
#ifndef MANYWORLDS_NN_PACO_H_
#define MANYWORLDS_NN_PACO_H_

#include "manyworlds/nn/task_trunks.h"

namespace manyworlds::nn {

class PacoTrunkImpl : public TrunkImpl {
 public:
  PacoTrunkImpl(const TaskTrunkOptions& options, c10::optional<at::Generator> generator);
  torch::Tensor Forward(const torch::Tensor& x, const torch::Tensor& task,
                        at::ArrayRef<torch::Tensor> params) const override;
  bool uses_task() const override { return true; }
  // The task weights (E, num_tasks, K), a view of the flat buffer (PaCo's
  // reset writes into it).
  torch::Tensor task_weights() const { return detached_params().back(); }

 private:
  TaskTrunkOptions options_;
  int64_t num_maps_ = 0;  // linear maps: num_layers + 1
};

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_PACO_H_
