#include "manyworlds/nn/gradnorm.h"

namespace manyworlds::nn {

GradNormTerms GradNormGradient(const torch::Tensor& weights, const torch::Tensor& losses,
                               const torch::Tensor& norms, const torch::Tensor& present,
                               torch::Tensor& initial_loss, double alpha) {
  torch::NoGradGuard no_grad;
  GradNormTerms terms;
  terms.grad = torch::zeros_like(weights);
  const double tasks = present.sum().item<double>();
  if (tasks == 0) return terms;
  initial_loss.copy_(torch::where(present & torch::isnan(initial_loss), losses, initial_loss));
  const torch::Tensor zero = torch::zeros_like(losses);
  const torch::Tensor ratio = torch::where(present, losses / initial_loss, zero);
  const torch::Tensor inverse_rate = ratio / (ratio.sum() / tasks + 1e-8);
  const torch::Tensor weighted = weights * norms;
  const torch::Tensor mean_weighted = torch::where(present, weighted, zero).sum() / tasks;
  const torch::Tensor target = mean_weighted * inverse_rate.pow(alpha);
  const torch::Tensor diff = torch::where(present, weighted - target, zero);
  // d/dw_t |w_t G_t - target_t| = sign(.) G_t, averaged over the tasks.
  terms.grad = torch::sign(diff) * norms / tasks;
  terms.loss = diff.abs().sum().item<double>() / tasks;
  return terms;
}

void RenormaliseTaskWeights(torch::Tensor& weights) {
  torch::NoGradGuard no_grad;
  weights.clamp_(1e-4);
  weights.mul_(static_cast<double>(weights.numel()) / weights.sum().item<double>());
}

}  // namespace manyworlds::nn
