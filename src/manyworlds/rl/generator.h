// Explicit torch generators: every random draw of a learner comes from a
// generator seeded from the run's seed and saved in its checkpoints.
#ifndef MANYWORLDS_RL_GENERATOR_H_
#define MANYWORLDS_RL_GENERATOR_H_

#include <cstdint>

#include <torch/torch.h>

namespace manyworlds::rl {

at::Generator MakeGenerator(uint64_t seed);
// The process-wide default CPU generator (torch::manual_seed's).
at::Generator& DefaultGenerator();
torch::Tensor GeneratorState(at::Generator& generator);
void SetGeneratorState(at::Generator& generator, const torch::Tensor& state);

}  // namespace manyworlds::rl

#endif  // MANYWORLDS_RL_GENERATOR_H_
