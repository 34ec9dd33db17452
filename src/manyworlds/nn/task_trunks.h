// The multi-task network architectures whose structure depends on the task
// (the "Meta-World+ table" architectures), one registry row each:
//   soft_modular  Soft Modularization (Yang et al. 2020): a routing network
//                 from the state and a task embedding mixes the modules of
//                 a modular base network, layer by layer (soft_modular.h);
//   paco          PaCo (Sun et al. 2022): every layer holds K parameter
//                 sets; a task's network is their combination with learned
//                 per-task weights (paco.h);
//   moore         MOORE (Hendawy et al. 2024): k expert MLPs whose outputs
//                 are made orthonormal by Gram-Schmidt, mixed with learned
//                 per-task weights, tanh, one output head per task (moore.h).
// Each is a TrunkImpl: SAC's actor uses one member, its twin critics an
// ensemble of two (every tensor gets a leading member dimension, so both
// critics run as one batched product per layer).
#ifndef MANYWORLDS_NN_TASK_TRUNKS_H_
#define MANYWORLDS_NN_TASK_TRUNKS_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/nn/trunk.h"

namespace manyworlds::nn {

struct TaskTrunkOptions {
  int64_t input_dim = 0;
  int64_t output_dim = 0;
  int64_t num_tasks = 1;
  int64_t ensemble_size = 1;  // members (critics: 2); Forward gives (E, B, out) when > 1
  int64_t hidden_dim = 400;   // width of the MLPs: MOORE's experts, PaCo's layers, SM's base
  int64_t num_layers = 3;     // MOORE: linear maps of an expert; PaCo: hidden layers
  int64_t num_experts = 4;    // MOORE
  int64_t num_param_sets = 5;  // PaCo
  // Soft Modularization: modules per layer, module layers, module width,
  // routing MLP layers and width.
  int64_t num_modules = 2;
  int64_t module_layers = 2;
  int64_t module_hidden = 256;
  int64_t routing_layers = 2;
  int64_t routing_hidden = 256;
};

struct TaskTrunkInfo {
  std::string name;
  std::string description;
  std::shared_ptr<TrunkImpl> (*make)(const TaskTrunkOptions& options,
                                     c10::optional<at::Generator> generator);
};

// The registry, in documentation order.
const std::vector<TaskTrunkInfo>& TaskTrunks();
// nullptr if `name` is not a task trunk.
const TaskTrunkInfo* LookupTaskTrunk(const std::string& name);
// A factory for GaussianPolicy / TwinCritic. Throws ConfigError on an
// unknown name; the networks it builds throw ConfigError on bad options.
TrunkFactory TaskTrunkFactory(const std::string& name, const TaskTrunkOptions& options);

// Initialisers the architectures share (in place, no grad).
// U(-bound, bound).
void InitUniform(const torch::Tensor& t, double bound, c10::optional<at::Generator> generator);
// Glorot/Xavier uniform for (..., in, out) weights: bound gain * sqrt(6 / (in + out)).
void InitXavierUniform(const torch::Tensor& weight, double gain,
                       c10::optional<at::Generator> generator);

// ConfigError "<what>: <field> must be > 0, got v" for the first
// non-positive value.
void RequirePositive(const char* what, std::initializer_list<std::pair<const char*, int64_t>> fields);

// A batched linear map over members: x (E, B, in), w (E, in, out), b (E, 1, out).
inline torch::Tensor MemberLinear(const torch::Tensor& x, const torch::Tensor& w,
                                  const torch::Tensor& b) {
  return torch::baddbmm(b, x, w);
}
// x (B, in) repeated for E members as a (E, B, in) view.
inline torch::Tensor ForMembers(const torch::Tensor& x, int64_t members) {
  return x.dim() == 3 ? x : x.unsqueeze(0).expand({members, x.size(0), x.size(1)});
}
// (E, B, out) -> (B, out) when there is one member.
inline torch::Tensor MemberOutput(const torch::Tensor& out, int64_t members) {
  return members == 1 ? out.squeeze(0) : out;
}
// ConfigError-free check used by every Forward: the task index is defined, (B) int64.
void CheckTrunkTask(const char* what, const torch::Tensor& task, int64_t rows);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_TASK_TRUNKS_H_
