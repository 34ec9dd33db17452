// Sub-archives of learner checkpoints: a module or a FlatAdam state stored
// under one key of the learner's archive (shared by every learner's
// Save/Load).
#ifndef MANYWORLDS_AGENTS_ARCHIVE_IO_H_
#define MANYWORLDS_AGENTS_ARCHIVE_IO_H_

#include <torch/torch.h>

#include "manyworlds/nn/flat_optim.h"

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

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_ARCHIVE_IO_H_
