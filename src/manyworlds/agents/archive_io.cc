#include "manyworlds/agents/archive_io.h"

namespace manyworlds::agents {

void WriteModule(torch::serialize::OutputArchive& archive, const char* key,
                 const torch::nn::Module& module) {
  torch::serialize::OutputArchive sub;
  module.save(sub);
  archive.write(key, sub);
}

void ReadModule(torch::serialize::InputArchive& archive, const char* key,
                torch::nn::Module& module) {
  torch::serialize::InputArchive sub;
  archive.read(key, sub);
  module.load(sub);
}

void WriteOptimizer(torch::serialize::OutputArchive& archive, const char* key,
                    const nn::FlatAdam& optimizer) {
  torch::serialize::OutputArchive sub;
  optimizer.Save(sub);
  archive.write(key, sub);
}

void ReadOptimizer(torch::serialize::InputArchive& archive, const char* key,
                   nn::FlatAdam& optimizer) {
  torch::serialize::InputArchive sub;
  archive.read(key, sub);
  optimizer.Load(sub);
}

}  // namespace manyworlds::agents
