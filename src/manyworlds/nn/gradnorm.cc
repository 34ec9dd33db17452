#include "manyworlds/nn/gradnorm.h"

#include <cmath>

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

std::pair<torch::Tensor, torch::Tensor> TaskLossesAndGradNorms(
    const torch::Tensor& per_sample, const torch::Tensor& task_index, int64_t num_tasks,
    const std::vector<torch::Tensor>& layers) {
  torch::Tensor losses = torch::zeros({num_tasks}, torch::kFloat32);
  torch::Tensor norms = torch::zeros({num_tasks}, torch::kFloat32);
  for (int64_t t = 0; t < num_tasks; ++t) {
    const torch::Tensor rows = torch::nonzero(task_index == t).reshape({-1});
    if (rows.numel() == 0) continue;
    const torch::Tensor loss = per_sample.index_select(0, rows).mean();
    // Only those layers' gradients: the backward stops there.
    const std::vector<torch::Tensor> grads =
        torch::autograd::grad({loss}, layers, {}, /*retain_graph=*/true);
    std::vector<torch::Tensor> flat;
    for (const torch::Tensor& g : grads) flat.push_back(g.reshape({-1}));
    losses[t] = loss.detach();
    norms[t] = torch::cat(flat).norm();
  }
  return {losses, norms};
}

GradNormState::GradNormState(int64_t num_tasks, const AdamOptions& adam)
    : weights(torch::ones({num_tasks}, torch::kFloat32)),
      initial_loss(torch::full({num_tasks}, std::nan(""), torch::kFloat32)),
      optimizer(num_tasks, adam) {}

double GradNormState::Step(const torch::Tensor& losses, const torch::Tensor& norms,
                           const torch::Tensor& present, double alpha) {
  const GradNormTerms terms =
      GradNormGradient(weights, losses, norms, present, initial_loss, alpha);
  optimizer.Step(weights, terms.grad);
  RenormaliseTaskWeights(weights);
  return terms.loss;
}

}  // namespace manyworlds::nn
