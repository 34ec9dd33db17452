#include "manyworlds/nn/task_encoder.h"

#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/mlp.h"

namespace manyworlds::nn {
namespace {

void RequirePositive(int64_t value, const char* what, const char* field) {
  if (value > 0) return;
  throw ConfigError(std::string(what) + ": " + field + " must be > 0, got " +
                    std::to_string(value));
}

}  // namespace

TaskEncoderImpl::TaskEncoderImpl(const TaskEncoderOptions& options,
                                 c10::optional<at::Generator> generator)
    : FlatModule("TaskEncoder"), options_(options) {
  RequirePositive(options.num_tasks, "TaskEncoder", "num_tasks");
  RequirePositive(options.embedding_dim, "TaskEncoder", "embedding_dim");
  RequirePositive(options.output_dim, "TaskEncoder", "output_dim");
  const bool pretrained = options.pretrained.defined();
  if (pretrained && (options.pretrained.dim() != 2 ||
                     options.pretrained.size(0) != options.num_tasks ||
                     options.pretrained.size(1) <= 0)) {
    throw ConfigError("TaskEncoder: pretrained task vectors must be (" +
                      std::to_string(options.num_tasks) + ", D)");
  }
  if (pretrained) options_.pretrained = options.pretrained.to(torch::kFloat32).contiguous();
  const int64_t e = options.embedding_dim;
  std::vector<ParamSpec> specs;
  if (pretrained) {
    const int64_t d = options.pretrained.size(1);
    specs = {{"proj0_w", {d, 2 * e}}, {"proj0_b", {2 * e}}, {"proj1_w", {2 * e, e}},
             {"proj1_b", {e}}};
  } else {
    specs = {{"embedding", {options.num_tasks, e}}};
  }
  const size_t head = specs.size();
  MlpOptions mlp;
  mlp.input_dim = options.embedding_dim;
  mlp.output_dim = options.output_dim;
  mlp.hidden_dim = options.hidden_dim;
  mlp.num_layers = options.num_layers;
  AppendMlpLayout(specs, "mlp_", mlp, /*ensemble=*/false);
  InitFlat(std::move(specs));
  torch::NoGradGuard no_grad;
  const std::vector<torch::Tensor>& views = detached_params();
  if (pretrained) {
    InitMlpParams(at::ArrayRef<torch::Tensor>(views).slice(0, head), generator);
  } else {
    views[0].copy_(torch::randn(views[0].sizes(), generator, torch::kFloat32));
  }
  InitMlpParams(at::ArrayRef<torch::Tensor>(views).slice(head), generator);
}

torch::Tensor TaskEncoderImpl::Encode(at::ArrayRef<torch::Tensor> params) const {
  if (params.size() != this->params().size()) {
    throw Error("TaskEncoder: expects " + std::to_string(this->params().size()) +
                " parameter tensors, got " + std::to_string(params.size()));
  }
  if (!options_.pretrained.defined()) return MlpForward(torch::relu(params[0]), params.slice(1));
  torch::Tensor h = torch::relu(options_.pretrained);
  h = torch::relu(torch::addmm(params[1], h, params[0]));
  h = torch::relu(torch::addmm(params[3], h, params[2]));
  return MlpForward(h, params.slice(4));
}

MixtureEncoderImpl::MixtureEncoderImpl(const MixtureEncoderOptions& options,
                                       c10::optional<at::Generator> generator)
    : FlatModule("MixtureEncoder"), options_(options) {
  RequirePositive(options.num_experts, "MixtureEncoder", "num_experts");
  RequirePositive(options.context_dim, "MixtureEncoder", "context_dim");
  if (!(options.temperature > 0.0)) {
    throw ConfigError("MixtureEncoder: temperature must be > 0, got " +
                      std::to_string(options.temperature));
  }
  MlpOptions experts;
  experts.input_dim = options.input_dim;
  experts.output_dim = options.output_dim;
  experts.hidden_dim = options.hidden_dim;
  experts.num_layers = options.num_layers;
  experts.ensemble_size = options.num_experts;
  MlpOptions selector;
  selector.input_dim = options.context_dim;
  selector.output_dim = options.num_experts;
  selector.hidden_dim = options.selector_hidden_dim;
  selector.num_layers = options.selector_num_layers;
  std::vector<ParamSpec> specs;
  num_expert_params_ = AppendMlpLayout(specs, "experts_", experts, /*ensemble=*/true);
  AppendMlpLayout(specs, "selector_", selector, /*ensemble=*/false);
  InitFlat(std::move(specs));
  InitMlpParams(detached_params(), generator);
}

torch::Tensor MixtureEncoderImpl::Weights(const torch::Tensor& context,
                                          at::ArrayRef<torch::Tensor> params) const {
  torch::Tensor logits = MlpForward(context, params.slice(num_expert_params_));
  if (options_.temperature != 1.0) logits = logits / options_.temperature;
  return torch::softmax(logits, -1);
}

torch::Tensor MixtureEncoderImpl::Experts(const torch::Tensor& x,
                                          at::ArrayRef<torch::Tensor> params) const {
  return MlpForward(x, params.slice(0, num_expert_params_));
}

torch::Tensor MixtureEncoderImpl::Mix(const torch::Tensor& x, const torch::Tensor& weights,
                                      at::ArrayRef<torch::Tensor> params) const {
  // (K, B, D) weighted by (B, K) and summed over experts. Elementwise on
  // purpose: a batched (B, 1, K) x (B, K, D) product is B tiny BLAS calls
  // (it made the whole SAC update 2.7x slower at B = 128).
  return (weights.t().unsqueeze(-1) * Experts(x, params)).sum(0);
}

}  // namespace manyworlds::nn
