#include "manyworlds/rl/generator.h"

#include <mutex>

#include <ATen/CPUGeneratorImpl.h>

namespace manyworlds::rl {

at::Generator MakeGenerator(uint64_t seed) { return at::detail::createCPUGenerator(seed); }

at::Generator& DefaultGenerator() {
  static at::Generator generator = at::detail::getDefaultCPUGenerator();
  return generator;
}

torch::Tensor GeneratorState(at::Generator& generator) {
  std::lock_guard<std::mutex> lock(generator.mutex());
  return generator.get_state();
}

void SetGeneratorState(at::Generator& generator, const torch::Tensor& state) {
  std::lock_guard<std::mutex> lock(generator.mutex());
  generator.set_state(state);
}

}  // namespace manyworlds::rl
