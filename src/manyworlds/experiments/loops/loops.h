// The family loops an algorithm's registry row (algorithms.cc) builds on:
//   off_policy.cc  SAC family: act, store transitions, replay updates per step
//   on_policy.cc   any OnPolicyLearner: rounds into a rollout buffer, one update
//   pearl_loop.cc  PEARL: prior and posterior rounds per task, per-task replay updates
#ifndef MANYWORLDS_EXPERIMENTS_LOOPS_LOOPS_H_
#define MANYWORLDS_EXPERIMENTS_LOOPS_LOOPS_H_

#include <cstdint>
#include <functional>
#include <memory>

#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/policy_gradient/policy_gradient.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/experiments/algorithm.h"

namespace manyworlds::experiments {

// The off-policy loop around the learner make_learner builds; size (the
// learner's widest networks) sizes the memory check made before it is built.
struct OffPolicyNetworkSize {
  int64_t hidden_dim = 0;
  int64_t num_layers = 0;
};
using OffPolicyLearnerFactory =
    std::function<std::unique_ptr<agents::OffPolicyLearner>(const AlgorithmSetup& setup)>;
std::unique_ptr<Algorithm> MakeOffPolicyAlgorithm(const AlgorithmSetup& setup,
                                                  const OffPolicyNetworkSize& size,
                                                  const OffPolicyLearnerFactory& make_learner);
// The registry's rows: SAC (and its variants), Distral.
std::unique_ptr<Algorithm> MakeSacAlgorithm(const AlgorithmSetup& setup);
std::unique_ptr<Algorithm> MakeDistralAlgorithm(const AlgorithmSetup& setup);
std::unique_ptr<Algorithm> MakeSacAeAlgorithm(const AlgorithmSetup& setup);
std::unique_ptr<Algorithm> MakeDeepMdpAlgorithm(const AlgorithmSetup& setup);
std::unique_ptr<Algorithm> MakeHipBmdpAlgorithm(const AlgorithmSetup& setup);
std::unique_ptr<Algorithm> MakePearlAlgorithm(const AlgorithmSetup& setup);
// The on-policy loop around `learner`, collecting `rounds` rounds of every
// env per update.
std::unique_ptr<Algorithm> MakeOnPolicyAlgorithm(const AlgorithmSetup& setup,
                                                 std::unique_ptr<agents::OnPolicyLearner> learner,
                                                 int64_t rounds);

// The spaces a learner of this setup acts in.
agents::PolicySpaces SetupSpaces(const AlgorithmSetup& setup);

// The algorithm's config with agent.seed mixed with experiment.seed.
template <class Config>
Config SeededAgentConfig(const AlgorithmSetup& setup) {
  Config c = setup.config.agent.as<Config>();
  c.seed = MixSeed(MixSeed(setup.config.experiment.seed, kAgentStream), c.seed);
  return c;
}

// An on-policy learner (constructed from its config and the spaces) in the
// on-policy loop; its config says how many rounds an iteration collects.
template <class Learner, class Config>
std::unique_ptr<Algorithm> MakeOnPolicy(const AlgorithmSetup& setup) {
  const Config c = SeededAgentConfig<Config>(setup);
  return MakeOnPolicyAlgorithm(setup, std::make_unique<Learner>(c, SetupSpaces(setup)),
                               c.RoundsPerIteration());
}

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_LOOPS_LOOPS_H_
