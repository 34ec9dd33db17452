// The algorithm registry: every algorithm `agent.algo` can name, with its
// family and config. An explicit list (algorithms.cc), in documentation
// order; unknown names are errors that list the valid ones.
//
//   name   family      config                       learner
//   sac    off-policy  agents/sac_config.h          agents/sac.h (MT-SAC, multi-head,
//                                                   task encoder, CARE, PCGrad)
//   ppo    on-policy   agents/ppo/ppo_config.h      agents/ppo/ppo.h (PPO, MT-PPO)
//   trpo   on-policy   agents/trpo/trpo_config.h    agents/trpo/trpo.h (TRPO, MT-TRPO)
//   te_ppo on-policy   agents/te_ppo/te_ppo_config.h agents/te_ppo/te_ppo.h (TE-PPO)
//   rl2    on-policy   agents/rl2/rl2_config.h      agents/rl2/rl2.h (RL2-PPO, trials)
//   maml   on-policy   agents/maml/maml_config.h    agents/maml/maml.h (MAML-TRPO, trials)
//   pearl  off-policy  agents/pearl/pearl_config.h  agents/pearl/pearl.h (PEARL, per-task
//                                                   replay; loop in pearl_loop.cc)
//
// This header is torch-free: configs can be read, printed and validated
// without the networks. MakeAlgorithm (algorithm.h) builds the learner.
#ifndef MANYWORLDS_EXPERIMENTS_ALGORITHMS_H_
#define MANYWORLDS_EXPERIMENTS_ALGORITHMS_H_

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/experiments/task_set.h"
#include "manyworlds/experiments/train_config.h"

namespace manyworlds::experiments {

enum class AlgorithmFamily { kOffPolicy, kOnPolicy };

struct AlgorithmInfo {
  std::string name;
  AlgorithmFamily family;
  bool discrete_actions;  // accepts Discrete action spaces
  bool box_actions;       // accepts Box action spaces
  std::string description;
};

const std::vector<AlgorithmInfo>& Algorithms();
// ConfigError naming the valid algorithms (and the nearest one) if unknown.
const AlgorithmInfo& FindAlgorithm(const std::string& name);
// The registered names, comma-separated in registry order (help texts and errors).
std::string AlgorithmNames();
const char* FamilyName(AlgorithmFamily family);

// The default config of an algorithm.
AgentConfig DefaultAgentConfig(const std::string& algo);
// Reads the agent section: `algo` (default "sac") and that algorithm's keys;
// unknown keys are errors (path "agent").
AgentConfig ReadAgentConfig(const nlohmann::json& section);
// Every key, defaults included, `algo` first.
nlohmann::json AgentConfigToJson(const AgentConfig& agent);
// ConfigError naming the first bad field.
void ValidateAgentConfig(const AgentConfig& agent);
// ConfigError if the algorithm cannot act in these envs (e.g. a
// continuous-only algorithm asked to handle a Discrete action space).
void CheckAlgorithmEnvs(const AgentConfig& agent, const EnvFacts& facts, const TaskSet& tasks);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_ALGORITHMS_H_
