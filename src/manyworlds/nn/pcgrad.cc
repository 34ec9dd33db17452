#include "manyworlds/nn/pcgrad.h"

#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {

PcGradResult ProjectConflictingGradients(const torch::Tensor& grads, at::Generator& generator) {
  if (!grads.defined() || grads.dim() != 2 || grads.size(0) < 1 ||
      grads.scalar_type() != torch::kFloat32 || !grads.device().is_cpu()) {
    throw Error("ProjectConflictingGradients: expected a CPU float32 (T, N) tensor, T >= 1");
  }
  const int64_t t = grads.size(0);
  torch::NoGradGuard no_grad;
  // Gram matrix in double for the coefficient arithmetic.
  const torch::Tensor gram = grads.mm(grads.t()).to(torch::kFloat64).contiguous();
  const double* g = gram.data_ptr<double>();
  // g_i' = sum_k c[i][k] g_k, starting from the identity.
  std::vector<double> c(static_cast<size_t>(t * t), 0.0);
  for (int64_t i = 0; i < t; ++i) c[i * t + i] = 1.0;
  PcGradResult result;
  result.pairs = t * (t - 1);
  for (int64_t i = 0; i < t; ++i) {
    for (int64_t j = 0; j < t; ++j) {
      if (j != i && g[i * t + j] < 0.0) ++result.conflicts;
    }
    if (t == 1) break;  // nothing to project against (and no draw)
    const torch::Tensor order = torch::randperm(t, generator, torch::kInt64);
    const int64_t* o = order.data_ptr<int64_t>();
    for (int64_t n = 0; n < t; ++n) {
      const int64_t j = o[n];
      const double norm2 = g[j * t + j];
      if (j == i || !(norm2 > 0.0)) continue;
      double dot = 0.0;  // g_i' . g_j
      for (int64_t k = 0; k < t; ++k) dot += c[i * t + k] * g[k * t + j];
      if (dot < 0.0) {
        c[i * t + j] -= dot / norm2;
        ++result.projections;
      }
    }
  }
  // mean_i g_i' = sum_k (mean_i c[i][k]) g_k.
  torch::Tensor weights = torch::zeros({1, t}, torch::kFloat64);
  double* w = weights.data_ptr<double>();
  for (int64_t i = 0; i < t; ++i) {
    for (int64_t k = 0; k < t; ++k) w[k] += c[i * t + k] / static_cast<double>(t);
  }
  result.gradient = weights.to(torch::kFloat32).mm(grads).squeeze(0);
  return result;
}

PcGradResult PcGradBackward(const torch::Tensor& per_sample, const torch::Tensor& task_index,
                            int64_t num_tasks, const std::vector<FlatModule*>& modules,
                            at::Generator& generator) {
  // Mean loss of each task present in the batch.
  const torch::Tensor counts = torch::bincount(task_index, {}, num_tasks);
  const torch::Tensor present = counts.nonzero().squeeze(1);
  const torch::Tensor task_loss = torch::zeros({num_tasks}, per_sample.options())
                                      .index_add(0, task_index, per_sample)
                                      .div(counts.clamp_min(1).to(per_sample.scalar_type()));
  int64_t total = 0;
  for (FlatModule* m : modules) total += m->num_params();
  const int64_t t = present.size(0);
  torch::Tensor grads = torch::empty({t, total}, torch::kFloat32);
  const int64_t* tasks = present.data_ptr<int64_t>();
  for (int64_t i = 0; i < t; ++i) {
    for (FlatModule* m : modules) m->ZeroGrad();
    task_loss[tasks[i]].backward({}, /*retain_graph=*/i + 1 < t);
    int64_t offset = 0;
    for (FlatModule* m : modules) {
      grads[i].narrow(0, offset, m->num_params()).copy_(m->flat_grad());
      offset += m->num_params();
    }
  }
  PcGradResult combined = ProjectConflictingGradients(grads, generator);
  int64_t offset = 0;
  for (FlatModule* m : modules) {
    m->flat_grad().copy_(combined.gradient.narrow(0, offset, m->num_params()));
    offset += m->num_params();
  }
  return combined;
}

}  // namespace manyworlds::nn
