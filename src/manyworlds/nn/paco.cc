#include "manyworlds/nn/paco.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/mlp.h"

namespace manyworlds::nn {

PacoTrunkImpl::PacoTrunkImpl(const TaskTrunkOptions& options,
                             c10::optional<at::Generator> generator)
    : TrunkImpl("PacoTrunk"), options_(options), num_maps_(options.num_layers + 1) {
  RequirePositive("paco", {{"input_dim", options.input_dim},
                           {"output_dim", options.output_dim},
                           {"num_tasks", options.num_tasks},
                           {"ensemble_size", options.ensemble_size},
                           {"hidden_dim", options.hidden_dim},
                           {"num_param_sets", options.num_param_sets}});
  if (options.num_layers < 0) {
    throw ConfigError("paco: num_layers must be >= 0, got " + std::to_string(options.num_layers));
  }
  const int64_t e = options.ensemble_size, k = options.num_param_sets;
  std::vector<ParamSpec> specs;
  std::vector<int64_t> widths = {options.input_dim};
  for (int64_t l = 0; l < options.num_layers; ++l) widths.push_back(options.hidden_dim);
  widths.push_back(options.output_dim);
  for (int64_t l = 0; l < num_maps_; ++l) {
    const std::string s = std::to_string(l);
    specs.push_back({"w" + s, {e, widths[l], k * widths[l + 1]}});
    specs.push_back({"b" + s, {e, 1, k * widths[l + 1]}});
  }
  specs.push_back({"task_weights", {e, options.num_tasks, k}});
  InitFlat(std::move(specs));

  torch::NoGradGuard no_grad;
  const std::vector<torch::Tensor>& p = detached_params();
  for (int64_t l = 0; l < num_maps_; ++l) {
    const int64_t in = widths[l], out = widths[l + 1];
    torch::Tensor first = torch::empty({e, in, out}, torch::kFloat32);
    InitOrthogonal(first, generator);
    // Identical sets: set j of the layer is columns [j out, (j + 1) out).
    p[2 * l].view({e, in, k, out}).copy_(first.unsqueeze(2).expand({e, in, k, out}));
    p[2 * l + 1].zero_();
  }
  p.back().normal_(0.0, 1.0 / std::sqrt(static_cast<double>(options.num_tasks)), generator);
}

torch::Tensor PacoTrunkImpl::Forward(const torch::Tensor& x, const torch::Tensor& task,
                                     at::ArrayRef<torch::Tensor> params) const {
  if (static_cast<int64_t>(params.size()) != 2 * num_maps_ + 1) {
    throw Error("PacoTrunk: expected " + std::to_string(2 * num_maps_ + 1) +
                " parameter tensors, got " + std::to_string(params.size()));
  }
  CheckTrunkTask("PacoTrunk", task, x.size(-2));
  const int64_t e = options_.ensemble_size, k = options_.num_param_sets, b = x.size(-2);
  // Rows grouped by task, equally many per task (balanced replay batches, one
  // env per task): compose each task's parameters once per layer and run one
  // product for all tasks. That costs one product of the layer instead of K.
  const torch::Tensor counts = torch::bincount(task, {}, options_.num_tasks);
  const torch::Tensor present = torch::nonzero(counts).reshape({-1});
  const int64_t tasks = present.numel();
  const int64_t per_task = b / std::max<int64_t>(tasks, 1);
  if (tasks > 0 && per_task * tasks == b &&
      (counts.index_select(0, present) == per_task).all().item<bool>()) {
    const torch::Tensor order = torch::argsort(task, /*stable=*/true);
    const torch::Tensor inverse = torch::argsort(order);
    // (E, P, 1, K): the present tasks' combination weights, in task order.
    const torch::Tensor w = params.back().index_select(1, present).unsqueeze(2);
    torch::Tensor h = ForMembers(x, e).index_select(1, order);  // (E, B, in), grouped
    for (int64_t l = 0; l < num_maps_; ++l) {
      const torch::Tensor& weight = params[2 * l];  // (E, in, K * out)
      const int64_t in = weight.size(1), out = weight.size(2) / k;
      // (E, P, K) x (E, K, in * out) -> each task's (in, out) weights.
      const torch::Tensor sets = weight.view({e, in, k, out}).permute({0, 2, 1, 3}).reshape(
          {e, k, in * out});
      const torch::Tensor composed = torch::bmm(w.view({e, tasks, k}), sets);
      const torch::Tensor bias =
          torch::bmm(w.view({e, tasks, k}), params[2 * l + 1].view({e, k, out}));
      h = torch::baddbmm(bias.reshape({e * tasks, 1, out}), h.reshape({e * tasks, per_task, in}),
                         composed.reshape({e * tasks, in, out}))
              .view({e, b, out});
      if (l + 1 < num_maps_) h = torch::relu(h);
    }
    return MemberOutput(h.index_select(1, inverse), e);
  }
  // Any other batch: all K pre-activations in one product, (E, B, K * out) ->
  // (E, B, K, out), combined by each row's weights (E, B, 1, K).
  const torch::Tensor w = params.back().index_select(1, task).unsqueeze(2);
  torch::Tensor h = ForMembers(x, e);
  for (int64_t l = 0; l < num_maps_; ++l) {
    const torch::Tensor& weight = params[2 * l];
    const int64_t out = weight.size(2) / k;
    h = torch::matmul(w, MemberLinear(h, weight, params[2 * l + 1]).view({e, b, k, out}))
            .squeeze(2);
    if (l + 1 < num_maps_) h = torch::relu(h);
  }
  return MemberOutput(h, e);
}

}  // namespace manyworlds::nn
