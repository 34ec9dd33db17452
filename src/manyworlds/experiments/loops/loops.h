// The family loops an algorithm's registry row (algorithms.cc) builds on:
//   off_policy.cc  SAC family: act, store transitions, replay updates per step
//   on_policy.cc   any OnPolicyLearner: rounds into a rollout buffer, one update
//   pearl_loop.cc  PEARL: prior and posterior rounds per task, per-task replay updates
#ifndef MANYWORLDS_EXPERIMENTS_LOOPS_LOOPS_H_
#define MANYWORLDS_EXPERIMENTS_LOOPS_LOOPS_H_

#include <cstdint>
#include <memory>

#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/policy_gradient/policy_gradient.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/experiments/algorithm.h"

namespace manyworlds::experiments {

std::unique_ptr<Algorithm> MakeOffPolicyAlgorithm(const AlgorithmSetup& setup);
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
