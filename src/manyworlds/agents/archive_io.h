// Sub-archives of learner checkpoints: a module or a FlatAdam state stored
// under one key of the learner's archive (shared by every learner's
// Save/Load), and the entries every checkpoint begins or ends with.
#ifndef MANYWORLDS_AGENTS_ARCHIVE_IO_H_
#define MANYWORLDS_AGENTS_ARCHIVE_IO_H_

#include <cstdint>
#include <memory>
#include <string>

#include <torch/torch.h>

#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/gradnorm.h"
#include "manyworlds/rl/linear_baseline.h"

namespace manyworlds::agents {

void WriteModule(torch::serialize::OutputArchive& archive, const char* key,
                 const torch::nn::Module& module);
// Throws (c10::Error) if the key is missing or the module's layout differs.
void ReadModule(torch::serialize::InputArchive& archive, const char* key,
                torch::nn::Module& module);
void WriteOptimizer(torch::serialize::OutputArchive& archive, const char* key,
                    const nn::FlatAdam& optimizer);
// Throws Error if the saved state is of another size.
void ReadOptimizer(torch::serialize::InputArchive& archive, const char* key,
                   nn::FlatAdam& optimizer);

// Transfer writes into an OutputArchive and reads from an InputArchive, so a
// learner's Save and Load can walk one list of its parts.
inline void Transfer(torch::serialize::OutputArchive& archive, const char* key,
                     const torch::nn::Module& module) {
  WriteModule(archive, key, module);
}
inline void Transfer(torch::serialize::InputArchive& archive, const char* key,
                     torch::nn::Module& module) {
  ReadModule(archive, key, module);
}
inline void Transfer(torch::serialize::OutputArchive& archive, const char* key,
                     const nn::FlatAdam& optimizer) {
  WriteOptimizer(archive, key, optimizer);
}
inline void Transfer(torch::serialize::InputArchive& archive, const char* key,
                     nn::FlatAdam& optimizer) {
  ReadOptimizer(archive, key, optimizer);
}
// GradNorm's state (nn/gradnorm.h) as three entries: KEY_weights,
// KEY_initial and KEY_optimizer. Reading checks the number of tasks.
void Transfer(torch::serialize::OutputArchive& archive, const std::string& key,
              const nn::GradNormState& state);
void Transfer(torch::serialize::InputArchive& archive, const std::string& key,
              nn::GradNormState& state);
// A linear baseline is stored as its coefficients tensor.
void Transfer(torch::serialize::OutputArchive& archive, const char* key,
              const rl::LinearFeatureBaseline& baseline);
void Transfer(torch::serialize::InputArchive& archive, const char* key,
              rl::LinearFeatureBaseline& baseline);

// The baseline of PPO, TRPO and TE-PPO: the value network ("value") and its
// optimizer ("value_optimizer") if there is one, else the linear baseline
// ("linear_baseline").
template <typename Archive, typename ValueNetwork, typename Optimizer>
void TransferBaseline(Archive& archive, ValueNetwork& value, Optimizer& value_optimizer,
                      const std::unique_ptr<rl::LinearFeatureBaseline>& linear) {
  if (value) {
    Transfer(archive, "value", *value);
    Transfer(archive, "value_optimizer", value_optimizer);
  } else {
    Transfer(archive, "linear_baseline", *linear);
  }
}

// The last entries of every learner's checkpoint: the update counter
// ("num_updates") and the state of the learner's generator ("generator").
void WriteProgress(torch::serialize::OutputArchive& archive, int64_t num_updates,
                   const at::Generator& generator);
void ReadProgress(torch::serialize::InputArchive& archive, int64_t& num_updates,
                  at::Generator& generator);

// The first entries of a MAML, RL2 or PEARL checkpoint: the algorithm's code
// ("algo") and the sizes its networks were built with ("sizes").
void WriteSignature(torch::serialize::OutputArchive& archive, int64_t code,
                    at::ArrayRef<int64_t> sizes);
// True if the archive starts with this code and these sizes.
bool HasSignature(torch::serialize::InputArchive& archive, int64_t code,
                  at::ArrayRef<int64_t> sizes);

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_ARCHIVE_IO_H_
