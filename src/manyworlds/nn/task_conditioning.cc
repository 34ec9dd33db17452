#include "manyworlds/nn/task_conditioning.h"

#include <algorithm>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {

const std::vector<std::string>& TaskConditioningArchitectures() {
  static const std::vector<std::string> names = {"mlp", "multihead", "task_encoder", "moe"};
  return names;
}

TaskEncoderOptions ConditioningTaskEncoderOptions(int64_t num_tasks, int64_t embedding_dim) {
  TaskEncoderOptions options;
  options.num_tasks = num_tasks;
  options.embedding_dim = embedding_dim;
  options.hidden_dim = embedding_dim;
  options.output_dim = embedding_dim;
  return options;
}

MixtureEncoderOptions ConditioningMixtureOptions(int64_t obs_dim, int64_t embedding_dim,
                                                 int64_t encoder_dim, int64_t num_experts) {
  return {.input_dim = obs_dim,
          .context_dim = embedding_dim,
          .output_dim = encoder_dim,
          .hidden_dim = encoder_dim,
          .num_experts = num_experts,
          .selector_hidden_dim = embedding_dim};
}

TaskConditioning::TaskConditioning(const TaskConditioningOptions& options,
                                   at::Generator& generator)
    : options_(options) {
  const auto& names = TaskConditioningArchitectures();
  if (std::find(names.begin(), names.end(), options.architecture) == names.end()) {
    throw ConfigError("task conditioning: unknown architecture '" + options.architecture +
                      "'; allowed: mlp, multihead, task_encoder, moe");
  }
  if (options.obs_dim <= 0 || options.num_tasks <= 0) {
    throw ConfigError("task conditioning: obs_dim and num_tasks must be > 0");
  }
  const std::string& arch = options.architecture;
  output_dim_ = options.obs_dim;
  if (arch == "mlp" && options.num_tasks > 1) output_dim_ += options.num_tasks;
  if (arch == "task_encoder" || arch == "moe") {
    task_encoder_ = TaskEncoder(
        ConditioningTaskEncoderOptions(options.num_tasks, options.task_embedding_dim), generator);
    modules_.push_back(task_encoder_.get());
    output_dim_ = options.obs_dim + options.task_embedding_dim;
  }
  if (arch == "moe") {
    mixture_ = MixtureEncoder(
        ConditioningMixtureOptions(options.obs_dim, options.task_embedding_dim,
                                   options.encoder_dim, options.num_experts),
        generator);
    modules_.push_back(mixture_.get());
    output_dim_ = options.encoder_dim + options.task_embedding_dim;
  }
}

torch::Tensor TaskConditioning::Forward(const torch::Tensor& obs,
                                        const torch::Tensor& task_index) const {
  if (obs.dim() != 2 || obs.size(1) != options_.obs_dim || task_index.dim() != 1 ||
      task_index.size(0) != obs.size(0)) {
    throw Error("task conditioning: expected obs (B, " + std::to_string(options_.obs_dim) +
                ") and task_index (B)");
  }
  if (!task_encoder_) {
    if (output_dim_ == options_.obs_dim) return obs;
    return torch::cat(
        {obs, torch::one_hot(task_index, options_.num_tasks).to(obs.scalar_type())}, -1);
  }
  const torch::Tensor encoding = task_encoder_->Encode(task_encoder_->params()).index_select(0, task_index);
  if (!mixture_) return torch::cat({obs, encoding}, -1);
  const torch::Tensor weights = mixture_->Weights(encoding, mixture_->params());
  return torch::cat({mixture_->Mix(obs, weights, mixture_->params()), encoding}, -1);
}

}  // namespace manyworlds::nn
