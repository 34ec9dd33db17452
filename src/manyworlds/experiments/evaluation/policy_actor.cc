#include "manyworlds/experiments/evaluation/policy_actor.h"

#include <utility>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"

namespace manyworlds::experiments {

PolicyActor::PolicyActor(std::string policy, uint64_t seed, std::function<Env&(int64_t)> env_of)
    : policy_(std::move(policy)), seed_(seed), env_of_(std::move(env_of)) {
  CheckPolicyName(policy_);
}

agents::ActOutput PolicyActor::Act(const torch::Tensor& obs, const torch::Tensor&,
                                   agents::ActorState&, agents::ActMode) {
  const int64_t n = obs.size(0);
  const torch::Tensor rows = obs.to(torch::kFloat32).contiguous();
  const int64_t obs_dim = rows.size(1);
  torch::Tensor action;
  for (int64_t i = 0; i < n; ++i) {
    Env& env = env_of_(i);
    if (static_cast<int64_t>(policies_.size()) <= i) policies_.resize(i + 1);
    if (!policies_[i]) {
      policies_[i] = MakePolicy(policy_, env, MixSeed(seed_, static_cast<uint64_t>(i)));
    }
    const int64_t action_dim = env.spec().action_space.flat_size();
    if (!action.defined()) action = torch::zeros({n, action_dim});
    if (env.elapsed_steps() == 0) policies_[i]->BeginEpisode();
    policies_[i]->Act({rows.data_ptr<float>() + i * obs_dim, static_cast<size_t>(obs_dim)}, {},
                      {action.data_ptr<float>() + i * action_dim, static_cast<size_t>(action_dim)});
  }
  agents::ActOutput out;
  out.action = action;
  out.log_prob = torch::zeros({n});
  return out;
}

EvalResult EvaluateEnvPolicy(const TrainConfig& config, const std::string& policy,
                             int64_t episodes, uint64_t seed) {
  config.Validate();
  const Registry& registry = DefaultRegistry();
  const TaskSet tasks = ResolveTasks(config.env, registry);
  Evaluator evaluator(tasks, registry, episodes, seed, config.experiment.num_threads);
  evaluator.TerminateOnSuccess(config.experiment.eval_terminate_on_success);
  PolicyActor actor(policy, seed, [&](int64_t i) -> Env& { return evaluator.env(i); });
  return evaluator.Run(actor);
}

MetaTestResult MetaTestEnvPolicy(const TrainConfig& config, const std::string& policy,
                                 uint64_t seed, bool on_training_tasks) {
  config.Validate();
  if (!on_training_tasks && !config.eval_env) {
    throw ConfigError("meta-test needs held-out tasks: the config has no eval_env section");
  }
  const Registry& registry = DefaultRegistry();
  const TaskSet tasks = on_training_tasks ? ResolveTasks(config.env, registry)
                                          : ResolveTasks(*config.eval_env, registry, "eval_env");
  MetaTestProtocol protocol(tasks, registry, config.meta_test, seed,
                            config.experiment.num_threads);
  PolicyActor actor(policy, seed, [&](int64_t i) -> Env& { return protocol.env(i); });
  return protocol.RunMetaTest(actor);
}

}  // namespace manyworlds::experiments
