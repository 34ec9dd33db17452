// Learned task encodings and a task-weighted mixture of state encoders
// (MTRL's agent/components/task_encoder.py and CARE's mixture of encoders,
// agent/components/moe_layer.py).
//
// TaskEncoder: Embedding(num_tasks, embedding_dim) -> ReLU -> MLP, one
// encoding per task. With pretrained vectors (CARE's task metadata: one
// fixed vector per task, e.g. an embedded description) the table is frozen
// and a learned projection maps it to embedding_dim first, as MTRL does:
// P -> ReLU -> Linear(D, 2E) -> ReLU -> Linear(2E, E) -> ReLU -> MLP. Encode() computes all num_tasks encodings at once (a
// tiny product); callers pick rows with the task index.
//
// MixtureEncoder: num_experts state encoders (MLPs of the same shape, run as
// one batched product) mixed per sample by attention weights computed from a
// task context: w = softmax(selector(context) / temperature), and
// encoding(x) = sum_k w_k expert_k(x). The selector is an MLP.
//
// Both keep all parameters in one flat buffer (FlatModule) and have
// functional forwards with explicit parameters, like Mlp.
#ifndef MANYWORLDS_NN_TASK_ENCODER_H_
#define MANYWORLDS_NN_TASK_ENCODER_H_

#include <cstdint>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"

namespace manyworlds::nn {

// Defaults are MTRL's (embedding 50, hidden 50, 2 hidden layers, output 50).
struct TaskEncoderOptions {
  int64_t num_tasks = 0;
  int64_t embedding_dim = 50;
  int64_t hidden_dim = 50;
  int64_t num_layers = 2;  // hidden layers of the MLP after the embedding
  int64_t output_dim = 50;
  // (num_tasks, D) float: fixed task vectors in place of the learned table.
  torch::Tensor pretrained;
};

class TaskEncoderImpl : public FlatModule {
 public:
  // Embedding rows ~ N(0, 1) (as torch::nn::Embedding), MLP orthogonal with
  // zero biases. Throws ConfigError on non-positive sizes.
  explicit TaskEncoderImpl(const TaskEncoderOptions& options,
                           c10::optional<at::Generator> generator = c10::nullopt);

  // All encodings, (num_tasks, output_dim).
  torch::Tensor forward() { return Encode(params()); }
  torch::Tensor Encode(at::ArrayRef<torch::Tensor> params) const;

  // The learned embedding table (num_tasks, embedding_dim), a parameter
  // view; with pretrained vectors, the first projection's weight.
  const torch::Tensor& embedding() const { return params()[0]; }
  // The fixed task vectors (undefined unless pretrained).
  const torch::Tensor& pretrained() const { return options_.pretrained; }
  const TaskEncoderOptions& options() const { return options_; }

 private:
  TaskEncoderOptions options_;
};
TORCH_MODULE(TaskEncoder);

struct MixtureEncoderOptions {
  int64_t input_dim = 0;    // state size
  int64_t context_dim = 0;  // task context (encoding) size
  int64_t output_dim = 50;  // encoder output size
  int64_t hidden_dim = 50;  // experts' hidden width
  int64_t num_layers = 2;   // experts' hidden layers
  int64_t num_experts = 4;
  int64_t selector_hidden_dim = 50;
  int64_t selector_num_layers = 2;
  double temperature = 1.0;
};

class MixtureEncoderImpl : public FlatModule {
 public:
  // Throws ConfigError on non-positive sizes or temperature.
  explicit MixtureEncoderImpl(const MixtureEncoderOptions& options,
                              c10::optional<at::Generator> generator = c10::nullopt);

  // context (N, context_dim) -> mixture weights (N, num_experts), rows sum to 1.
  torch::Tensor Weights(const torch::Tensor& context, at::ArrayRef<torch::Tensor> params) const;
  // x (B, input_dim) -> every expert's encoding (num_experts, B, output_dim).
  torch::Tensor Experts(const torch::Tensor& x, at::ArrayRef<torch::Tensor> params) const;
  // x (B, input_dim), weights (B, num_experts) -> (B, output_dim).
  torch::Tensor Mix(const torch::Tensor& x, const torch::Tensor& weights,
                    at::ArrayRef<torch::Tensor> params) const;

  const MixtureEncoderOptions& options() const { return options_; }

 private:
  MixtureEncoderOptions options_;
  size_t num_expert_params_ = 0;  // experts first, then the selector
};
TORCH_MODULE(MixtureEncoder);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_TASK_ENCODER_H_
