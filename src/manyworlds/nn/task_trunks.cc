#include "manyworlds/nn/task_trunks.h"

#include <cmath>
#include <string>
#include <utility>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/moore.h"
#include "manyworlds/nn/paco.h"
#include "manyworlds/nn/soft_modular.h"

namespace manyworlds::nn {
namespace {

template <class Impl>
std::shared_ptr<TrunkImpl> Make(const TaskTrunkOptions& options,
                                c10::optional<at::Generator> generator) {
  return std::make_shared<Impl>(options, generator);
}

}  // namespace

const std::vector<TaskTrunkInfo>& TaskTrunks() {
  // Append only: SAC checkpoints store an architecture by its place in
  // SacArchitectures(), which lists these after its own four.
  static const std::vector<TaskTrunkInfo> list = {
      {"soft_modular",
       "Soft Modularization: a routing network from state and task mixes the modules of each "
       "layer (Yang et al. 2020)",
       &Make<SoftModularTrunkImpl>},
      {"paco",
       "PaCo: per-task combinations of K shared parameter sets (Sun et al. 2022)",
       &Make<PacoTrunkImpl>},
      {"moore",
       "MOORE: Gram-Schmidt-orthogonalised experts mixed per task, one head per task "
       "(Hendawy et al. 2024)",
       &Make<MooreTrunkImpl>},
  };
  return list;
}

const TaskTrunkInfo* LookupTaskTrunk(const std::string& name) {
  for (const TaskTrunkInfo& info : TaskTrunks()) {
    if (info.name == name) return &info;
  }
  return nullptr;
}

TrunkFactory TaskTrunkFactory(const std::string& name, const TaskTrunkOptions& options) {
  const TaskTrunkInfo* info = LookupTaskTrunk(name);
  if (info == nullptr) throw ConfigError("unknown task trunk '" + name + "'");
  return [make = info->make, options](c10::optional<at::Generator> generator) {
    return make(options, generator);
  };
}

void InitUniform(const torch::Tensor& t, double bound, c10::optional<at::Generator> generator) {
  torch::NoGradGuard no_grad;
  t.uniform_(-bound, bound, generator);
}

void InitXavierUniform(const torch::Tensor& weight, double gain,
                       c10::optional<at::Generator> generator) {
  const double fans = static_cast<double>(weight.size(-2) + weight.size(-1));
  InitUniform(weight, gain * std::sqrt(6.0 / fans), generator);
}

void RequirePositive(const char* what,
                     std::initializer_list<std::pair<const char*, int64_t>> fields) {
  for (const auto& [field, value] : fields) {
    if (value <= 0) {
      throw ConfigError(std::string(what) + ": " + field + " must be > 0, got " +
                        std::to_string(value));
    }
  }
}

void CheckTrunkTask(const char* what, const torch::Tensor& task, int64_t rows) {
  if (!task.defined() || task.dim() != 1 || task.size(0) != rows ||
      task.scalar_type() != torch::kInt64) {
    throw Error(std::string(what) + ": needs the task index of every row, an int64 tensor of "
                "shape (" + std::to_string(rows) + ")");
  }
}

}  // namespace manyworlds::nn
