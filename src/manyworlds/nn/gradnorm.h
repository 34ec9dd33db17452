// GradNorm (Chen, Badrinarayanan, Lee, Rabinovich, ICML 2018): per-task loss
// weights w_t learned so that the weighted gradient norms w_t G_t of the
// tasks (G_t: the norm of task t's loss gradient in a shared layer) approach
// a common target scaled by each task's relative inverse training rate,
//   target_t = mean_s(w_s G_s) * (r_t / mean_s r_s)^alpha,  r_t = L_t / L_t(0),
// by gradient steps on mean_t |w_t G_t - target_t| with the target held
// fixed; after each step the weights are renormalised to sum to the number of
// tasks. Tasks absent from a batch take no part.
#ifndef MANYWORLDS_NN_GRADNORM_H_
#define MANYWORLDS_NN_GRADNORM_H_

#include <cstdint>
#include <utility>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/nn/flat_optim.h"

namespace manyworlds::nn {

struct GradNormTerms {
  torch::Tensor grad;  // (T) d/dw of the GradNorm loss
  double loss = 0.0;   // mean_t |w_t G_t - target_t| over the present tasks
};

// weights, losses, norms (T) float; present (T) bool; initial_loss (T), NaN
// where a task has no reference yet: set here to the task's current loss the
// first time it is present.
GradNormTerms GradNormGradient(const torch::Tensor& weights, const torch::Tensor& losses,
                               const torch::Tensor& norms, const torch::Tensor& present,
                               torch::Tensor& initial_loss, double alpha);

// In place: at least 1e-4 each, then scaled to sum to their number.
void RenormaliseTaskWeights(torch::Tensor& weights);

// Per-task mean losses (T) of per_sample (B) over the rows of each task in
// task_index (B), and the norms (T) of their gradients in `layers` (taken
// together, as one vector), unweighted; 0 for tasks absent from the batch.
// Keeps the graph for the loss's own backward.
std::pair<torch::Tensor, torch::Tensor> TaskLossesAndGradNorms(
    const torch::Tensor& per_sample, const torch::Tensor& task_index, int64_t num_tasks,
    const std::vector<torch::Tensor>& layers);

// GradNorm's state for one loss: the task weights, each task's first loss,
// the weights' Adam. Default-constructed: off (weights() undefined).
struct GradNormState {
  GradNormState() = default;
  GradNormState(int64_t num_tasks, const AdamOptions& adam);

  // One GradNorm step from a batch's per-task losses and gradient norms (T)
  // and the tasks present in it (T, bool): the weights' Adam step, then
  // their renormalisation. Returns the L1 GradNorm loss.
  double Step(const torch::Tensor& losses, const torch::Tensor& norms,
              const torch::Tensor& present, double alpha);

  torch::Tensor weights;       // (T), sum T
  torch::Tensor initial_loss;  // (T), NaN until the task was first seen
  FlatAdam optimizer{0, AdamOptions{}};
};

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_GRADNORM_H_
