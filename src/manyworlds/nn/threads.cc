#include "manyworlds/nn/threads.h"

#include <torch/torch.h>

namespace manyworlds::nn {

void ConfigureTorchThreads() {
  if (torch::get_num_threads() != 1) torch::set_num_threads(1);
}

}  // namespace manyworlds::nn
