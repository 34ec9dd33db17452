// PCGrad (Yu et al., "Gradient Surgery for Multi-Task Learning", 2020), the
// gradient combination MTRL's pcgrad agents use (agent/pcgrad.py).
//
// Given one gradient per task g_1..g_T, each task's gradient is projected
// away from every other task's gradient it conflicts with, visiting the
// others in a random order:
//   for j in shuffled(tasks other than i):
//     g_i' <- g_i' - min(0, g_i' . g_j) / |g_j|^2 g_j
// (g_j are the original gradients), and the result is the mean of the g_i'.
//
// The projections are done on coefficients over the Gram matrix G = g g^T
// (T x T, in double), so the cost is one (T, N) x (N, T) product for G and
// one (T) x (T, N) product for the result, whatever the order of projections.
#ifndef MANYWORLDS_NN_PCGRAD_H_
#define MANYWORLDS_NN_PCGRAD_H_

#include <cstdint>

#include <vector>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"

namespace manyworlds::nn {

struct PcGradResult {
  torch::Tensor gradient;   // (N) float32: mean of the projected task gradients
  int64_t conflicts = 0;    // ordered pairs (i, j), i != j, with g_i . g_j < 0
  int64_t projections = 0;  // projections applied (g_i' . g_j < 0 when visited)
  int64_t pairs = 0;        // T (T - 1)
  // conflicts / pairs (0 with one task).
  double conflict_fraction() const {
    return pairs > 0 ? static_cast<double>(conflicts) / static_cast<double>(pairs) : 0.0;
  }
};

// grads: (T, N) float32, one task gradient per row (T >= 1). The orders are
// drawn from `generator` (one torch::randperm(T) per task; none when T = 1).
// Throws Error on a tensor of another shape or type.
PcGradResult ProjectConflictingGradients(const torch::Tensor& grads, at::Generator& generator);

// PCGrad on a loss given per sample: the mean loss of each task present in
// task_index ((B) int64 in [0, num_tasks)) is backpropagated on its own
// through `modules`, the per-task flat gradients (modules concatenated in
// order) are combined as above, and the result is left in the modules'
// flat_grad() for the optimizer step. per_sample: (B), with autograd history.
PcGradResult PcGradBackward(const torch::Tensor& per_sample, const torch::Tensor& task_index,
                            int64_t num_tasks, const std::vector<FlatModule*>& modules,
                            at::Generator& generator);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_PCGRAD_H_
