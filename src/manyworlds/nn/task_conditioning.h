// The network input of a task-conditioned policy, x(obs, task), for the
// on-policy family (PPO, TRPO; SAC builds its own, with target encoders):
//   "mlp"          [obs, one-hot(task)] when there are several tasks, else obs;
//   "multihead"    obs (the task picks an output head elsewhere);
//   "task_encoder" [obs, e(task)], e a learned TaskEncoder (MTRL);
//   "moe"          [sum_k w_k(e(task)) expert_k(obs), e(task)], CARE's
//                  mixture of encoders with attention from the encoding.
// The learned parts are FlatModules trained by the policy's objective: PPO
// steps them with their own Adam, TRPO includes them in its natural-gradient
// step. Value functions read x detached.
#ifndef MANYWORLDS_NN_TASK_CONDITIONING_H_
#define MANYWORLDS_NN_TASK_CONDITIONING_H_

#include <cstdint>
#include <string>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"
#include "manyworlds/nn/task_encoder.h"

namespace manyworlds::nn {

struct TaskConditioningOptions {
  std::string architecture = "mlp";  // mlp | multihead | task_encoder | moe
  int64_t obs_dim = 0;
  int64_t num_tasks = 1;
  int64_t task_embedding_dim = 50;  // task_encoder, moe: embedding, hidden and output width
  int64_t num_experts = 4;          // moe
  int64_t encoder_dim = 50;         // moe: experts' output and hidden width
};

// The allowed architectures, in documentation order.
const std::vector<std::string>& TaskConditioningArchitectures();

// The learned parts of task_encoder and moe (SAC builds the same ones):
// a task encoder whose embedding, hidden layer and output are all
// embedding_dim wide, and a mixture of num_experts encoders of obs to
// encoder_dim (hidden width encoder_dim) weighted from that embedding.
TaskEncoderOptions ConditioningTaskEncoderOptions(int64_t num_tasks, int64_t embedding_dim);
MixtureEncoderOptions ConditioningMixtureOptions(int64_t obs_dim, int64_t embedding_dim,
                                                 int64_t encoder_dim, int64_t num_experts);

class TaskConditioning {
 public:
  // Draws the learned parts' initial values from `generator` (task encoder
  // first, then the mixture). Throws ConfigError on an unknown architecture
  // or bad sizes.
  TaskConditioning(const TaskConditioningOptions& options, at::Generator& generator);

  // obs (B, obs_dim), task_index (B) int64 -> x (B, output_dim()). Gradients
  // flow into the learned parts unless the caller is in no-grad mode.
  torch::Tensor Forward(const torch::Tensor& obs, const torch::Tensor& task_index) const;

  int64_t output_dim() const { return output_dim_; }
  bool multihead() const { return options_.architecture == "multihead"; }
  // The learned parts (empty for mlp and multihead), in a fixed order.
  const std::vector<FlatModule*>& modules() const { return modules_; }
  const TaskConditioningOptions& options() const { return options_; }

 private:
  TaskConditioningOptions options_;
  int64_t output_dim_ = 0;
  TaskEncoder task_encoder_{nullptr};
  MixtureEncoder mixture_{nullptr};
  std::vector<FlatModule*> modules_;
};

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_TASK_CONDITIONING_H_
