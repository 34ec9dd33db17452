// An Actor over the envs' own policies (core/policy.h): the scripted
// (expert) policy of each env, or uniform random actions from a stream per
// env. It lets the evaluation protocols run without a trained learner, which
// is how their equivalence with Meta-World v3's own evaluation functions is
// tested (python/tests/test_metaworld_protocols.py): the same policy driven
// by v3's code over our Python envs and by our protocols must score the same.
//
// Env i's policy is made at its first Act: MakePolicy(name, env,
// MixSeed(seed, i)) (envs/all.h: "scripted" or "random"). A policy's BeginEpisode is called when its env is at
// the first step of an episode (elapsed_steps 0), wherever the protocol
// reset it. Actions are in the env's units (ActsInEnvUnits).
#ifndef MANYWORLDS_EXPERIMENTS_EVALUATION_POLICY_ACTOR_H_
#define MANYWORLDS_EXPERIMENTS_EVALUATION_POLICY_ACTOR_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "manyworlds/agents/actor.h"
#include "manyworlds/core/env.h"
#include "manyworlds/core/policy.h"
#include "manyworlds/experiments/evaluation/evaluator.h"
#include "manyworlds/experiments/evaluation/meta_test_protocol.h"
#include "manyworlds/experiments/train_config.h"

namespace manyworlds::experiments {

class PolicyActor : public agents::Actor {
 public:
  // `env_of(i)`: the protocol's env i, alive as long as the actor acts.
  // Throws ConfigError for an unknown policy name.
  PolicyActor(std::string policy, uint64_t seed, std::function<Env&(int64_t)> env_of);

  agents::ActOutput Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                        agents::ActorState& state, agents::ActMode mode) override;
  bool ActsInEnvUnits() const override { return true; }

 private:
  std::string policy_;
  uint64_t seed_;
  std::function<Env&(int64_t)> env_of_;
  std::vector<std::unique_ptr<Policy>> policies_;
};

// A config's evaluation protocols with an env policy instead of a learner
// (`manyworlds eval CONFIG --policy scripted|random`): the multi-task
// evaluation on the config's tasks (episodes per task, ending at success as
// experiment.eval_terminate_on_success says), and the meta-test protocol
// (config.meta_test) on its held-out tasks (eval_env), or on its training
// tasks. `seed` seeds the protocol and the random policy. Throw ConfigError
// for a bad config, policy or protocol setup.
EvalResult EvaluateEnvPolicy(const TrainConfig& config, const std::string& policy,
                             int64_t episodes, uint64_t seed);
MetaTestResult MetaTestEnvPolicy(const TrainConfig& config, const std::string& policy,
                                 uint64_t seed, bool on_training_tasks);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_EVALUATION_POLICY_ACTOR_H_
