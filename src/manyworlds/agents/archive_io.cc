#include "manyworlds/agents/archive_io.h"

#include <utility>

#include "manyworlds/core/error.h"
#include "manyworlds/rl/generator.h"

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

void Transfer(torch::serialize::OutputArchive& archive, const char* key,
              const rl::LinearFeatureBaseline& baseline) {
  archive.write(key, baseline.coefficients());
}

void Transfer(torch::serialize::InputArchive& archive, const char* key,
              rl::LinearFeatureBaseline& baseline) {
  torch::Tensor coefficients;
  archive.read(key, coefficients);
  baseline.set_coefficients(coefficients);
}

void Transfer(torch::serialize::OutputArchive& archive, const std::string& key,
              const nn::GradNormState& state) {
  archive.write(key + "_weights", state.weights);
  archive.write(key + "_initial", state.initial_loss);
  WriteOptimizer(archive, (key + "_optimizer").c_str(), state.optimizer);
}

void Transfer(torch::serialize::InputArchive& archive, const std::string& key,
              nn::GradNormState& state) {
  for (const auto& [suffix, tensor] :
       {std::pair<const char*, torch::Tensor*>{"_weights", &state.weights},
        {"_initial", &state.initial_loss}}) {
    torch::Tensor saved;
    archive.read(key + suffix, saved);
    if (saved.numel() != tensor->numel()) {
      throw Error("checkpoint has GradNorm state '" + key + "' for " +
                  std::to_string(saved.numel()) + " tasks, this learner " +
                  std::to_string(tensor->numel()));
    }
    tensor->copy_(saved.reshape(tensor->sizes()));
  }
  ReadOptimizer(archive, (key + "_optimizer").c_str(), state.optimizer);
}

void WriteProgress(torch::serialize::OutputArchive& archive, int64_t num_updates,
                   const at::Generator& generator) {
  archive.write("num_updates", torch::tensor(num_updates, torch::kInt64));
  at::Generator shared = generator;  // the same generator; its state is read under its lock
  archive.write("generator", rl::GeneratorState(shared));
}

void ReadProgress(torch::serialize::InputArchive& archive, int64_t& num_updates,
                  at::Generator& generator) {
  torch::Tensor updates, state;
  archive.read("num_updates", updates);
  num_updates = updates.item<int64_t>();
  archive.read("generator", state);
  rl::SetGeneratorState(generator, state);
}

void WriteSignature(torch::serialize::OutputArchive& archive, int64_t code,
                    at::ArrayRef<int64_t> sizes) {
  archive.write("algo", torch::tensor(code, torch::kInt64));
  archive.write("sizes", torch::tensor(sizes, torch::kInt64));
}

bool HasSignature(torch::serialize::InputArchive& archive, int64_t code,
                  at::ArrayRef<int64_t> sizes) {
  torch::Tensor algo, saved;
  return archive.try_read("algo", algo) && algo.numel() == 1 && algo.item<int64_t>() == code &&
         archive.try_read("sizes", saved) &&
         torch::equal(saved, torch::tensor(sizes, torch::kInt64));
}

}  // namespace manyworlds::agents
