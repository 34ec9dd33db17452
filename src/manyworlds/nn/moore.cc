#include "manyworlds/nn/moore.h"

#include <cmath>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/mlp.h"

namespace manyworlds::nn {
namespace {

MlpOptions ExpertOptions(const TaskTrunkOptions& o) {
  MlpOptions m;
  m.input_dim = o.input_dim;
  m.output_dim = o.hidden_dim;
  m.hidden_dim = o.hidden_dim;
  m.num_layers = o.num_layers - 1;  // hidden layers; the last map is the output
  m.ensemble_size = o.ensemble_size * o.num_experts;
  return m;
}

}  // namespace

torch::Tensor GramSchmidt(const torch::Tensor& x) {
  const int64_t k = x.size(-2);
  std::vector<torch::Tensor> basis;
  basis.reserve(static_cast<size_t>(k));
  for (int64_t i = 0; i < k; ++i) {
    torch::Tensor v = x.select(-2, i);
    for (const torch::Tensor& u : basis) v = v - (v * u).sum(-1, true) * u;
    basis.push_back(v / torch::linalg_vector_norm(v, 2, {-1}, true).clamp_min(1e-12));
  }
  return torch::stack(basis, -2);
}

MooreTrunkImpl::MooreTrunkImpl(const TaskTrunkOptions& options,
                               c10::optional<at::Generator> generator)
    : TrunkImpl("MooreTrunk"), options_(options) {
  RequirePositive("moore", {{"input_dim", options.input_dim},
                            {"output_dim", options.output_dim},
                            {"num_tasks", options.num_tasks},
                            {"ensemble_size", options.ensemble_size},
                            {"hidden_dim", options.hidden_dim},
                            {"num_layers", options.num_layers},
                            {"num_experts", options.num_experts}});
  const int64_t e = options.ensemble_size;
  std::vector<ParamSpec> specs;
  expert_tensors_ = AppendMlpLayout(specs, "expert_", ExpertOptions(options), /*ensemble=*/true);
  specs.push_back({"task_weights", {e, options.num_tasks, options.num_experts}});
  specs.push_back({"head_w", {e, options.hidden_dim, options.num_tasks * options.output_dim}});
  specs.push_back({"head_b", {e, 1, options.num_tasks * options.output_dim}});
  InitFlat(std::move(specs));

  torch::NoGradGuard no_grad;
  const std::vector<torch::Tensor>& p = detached_params();
  const double relu_gain = std::sqrt(2.0);
  for (size_t i = 0; i < expert_tensors_; i += 2) {
    const bool last = i + 2 == expert_tensors_;
    InitXavierUniform(p[i], last ? 1.0 : relu_gain, generator);
    p[i + 1].zero_();
  }
  // The task encoder is Linear(num_tasks -> k): fan-in num_tasks, fan-out k.
  InitUniform(p[expert_tensors_],
              std::sqrt(6.0 / static_cast<double>(options.num_tasks + options.num_experts)),
              generator);
  // Each head is Linear(hidden -> out), Xavier with its own fans.
  InitUniform(p[expert_tensors_ + 1],
              std::sqrt(6.0 / static_cast<double>(options.hidden_dim + options.output_dim)),
              generator);
  p[expert_tensors_ + 2].zero_();
}

torch::Tensor MooreTrunkImpl::Forward(const torch::Tensor& x, const torch::Tensor& task,
                                      at::ArrayRef<torch::Tensor> params) const {
  if (params.size() != expert_tensors_ + 3) {
    throw Error("MooreTrunk: expected " + std::to_string(expert_tensors_ + 3) +
                " parameter tensors, got " + std::to_string(params.size()));
  }
  CheckTrunkTask("MooreTrunk", task, x.size(-2));
  const int64_t e = options_.ensemble_size, k = options_.num_experts, b = x.size(-2);
  const int64_t h = options_.hidden_dim;
  // (E*k, B, h) -> (E, B, k, h): the experts of each member side by side.
  const torch::Tensor experts =
      MlpForward(x, params.slice(0, expert_tensors_)).view({e, k, b, h}).transpose(1, 2);
  const torch::Tensor basis = GramSchmidt(experts);
  // Per-row weights (E, B, 1, k) times the basis (E, B, k, h).
  const torch::Tensor weights = params[expert_tensors_].index_select(1, task).unsqueeze(2);
  const torch::Tensor features = torch::tanh(torch::matmul(weights, basis).squeeze(2));
  const torch::Tensor all_heads =
      MemberLinear(features, params[expert_tensors_ + 1], params[expert_tensors_ + 2]);
  return MemberOutput(SelectHeads(all_heads, task, options_.output_dim), e);
}

}  // namespace manyworlds::nn
