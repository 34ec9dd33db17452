// Reading and writing the torch archive of a checkpoint with errors that
// name the file (shared by the algorithm families).
#ifndef MANYWORLDS_EXPERIMENTS_RUN_CHECKPOINT_IO_H_
#define MANYWORLDS_EXPERIMENTS_RUN_CHECKPOINT_IO_H_

#include <filesystem>
#include <functional>

#include <torch/torch.h>

namespace manyworlds::experiments {

void WriteArchive(const std::filesystem::path& file,
                  const std::function<void(torch::serialize::OutputArchive&)>& fill);
// Error naming the file if it is missing, corrupt or of another algorithm.
void ReadArchive(const std::filesystem::path& file,
                 const std::function<void(torch::serialize::InputArchive&)>& read);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_RUN_CHECKPOINT_IO_H_
