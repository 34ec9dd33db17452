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

#include <torch/torch.h>

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

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_GRADNORM_H_
