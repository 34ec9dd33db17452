// MOORE, a mixture of orthogonal experts (Hendawy, Peters, D'Eramo, ICLR
// 2024), as the authors' Meta-World SAC networks build it
// (AhmedMagdyHendawy/MOORE, moore/utils/networks_sac.py and
// mixture_layers.py, read as reference):
//   experts   k MLPs of the input: num_layers linear maps of width
//             hidden_dim, ReLU between, the last one linear
//             (`--activation Linear`);
//   Gram-Schmidt  per row, the k expert outputs become an orthonormal basis
//             (expert 0 normalised, each next one minus its projections,
//             normalised);
//   mixing    w(task) = a bias-free linear map of the one-hot task (k
//             weights), features = sum_i w_i basis_i, then tanh
//             (`--agg_activation Linear Tanh`);
//   heads     one linear output head per task (the multi-head variant the
//             MT10/MT50 scripts run).
// Differences: biases start at zero (PyTorch's default draws them
// uniformly); weights are Xavier-uniform with the authors' gains. The norms
// in Gram-Schmidt are clamped at 1e-12 so a zero expert output cannot divide
// by zero (the authors divide unguarded).
#ifndef MANYWORLDS_NN_MOORE_H_
#define MANYWORLDS_NN_MOORE_H_

#include "manyworlds/nn/task_trunks.h"

namespace manyworlds::nn {

// Rows of x (..., k, d) made orthonormal along k by Gram-Schmidt, in order.
torch::Tensor GramSchmidt(const torch::Tensor& x);

class MooreTrunkImpl : public TrunkImpl {
 public:
  MooreTrunkImpl(const TaskTrunkOptions& options, c10::optional<at::Generator> generator);
  torch::Tensor Forward(const torch::Tensor& x, const torch::Tensor& task,
                        at::ArrayRef<torch::Tensor> params) const override;
  bool uses_task() const override { return true; }

 private:
  TaskTrunkOptions options_;
  size_t expert_tensors_ = 0;  // params: experts' (w, b) pairs, task weights, head w, head b
};

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_MOORE_H_
