// The algorithm registry: the one list of the algorithms `agent.algo` can
// name (algorithms.cc). A row gives an algorithm's name, family, the action
// spaces it accepts, a description, its config type (default config, read,
// printed and validated through the config's VisitFields), the factory of its
// training loop and its update benchmark. Everything else that names
// algorithms (errors, --help, `bench agent`, the docs table) derives from the
// rows. Adding an algorithm: a folder under agents/ and one row
// (docs/contributing.md).
#ifndef MANYWORLDS_EXPERIMENTS_ALGORITHMS_H_
#define MANYWORLDS_EXPERIMENTS_ALGORITHMS_H_

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "manyworlds/experiments/agent_bench.h"
#include "manyworlds/experiments/agent_config.h"
#include "manyworlds/experiments/task_set.h"
#include "manyworlds/experiments/train_config.h"

namespace manyworlds::experiments {

enum class AlgorithmFamily { kOffPolicy, kOnPolicy };

// What an algorithm's policy acts on: the env observation (the state), the
// pixel frames of obs=pixels envs, or either (SAC: a convolutional encoder
// when the envs have frames).
enum class ObservationKind { kState, kPixels, kStateOrPixels };

class Algorithm;
struct AlgorithmSetup;
using AlgorithmFactory = std::unique_ptr<Algorithm> (*)(const AlgorithmSetup& setup);

struct AlgorithmInfo {
  std::string name;
  AlgorithmFamily family;
  bool discrete_actions;  // accepts Discrete action spaces
  bool box_actions;       // accepts Box action spaces
  std::string description;
  std::unique_ptr<AgentParams> (*default_config)();  // the config type, with its defaults
  AlgorithmFactory make;                             // its training loop (algorithm.h)
  AgentBench bench;                                  // `bench agent` (agent_bench.h)
  ObservationKind observations = ObservationKind::kState;
};

const std::vector<AlgorithmInfo>& Algorithms();
// ConfigError naming the valid algorithms (and the nearest one) if unknown.
const AlgorithmInfo& FindAlgorithm(const std::string& name);
// nullptr if unknown.
const AlgorithmInfo* LookupAlgorithm(const std::string& name);
// "<key>: unknown algorithm 'x' (did you mean ...); allowed: ..." (the error
// of FindAlgorithm, with another key, e.g. a command-line flag).
std::string UnknownAlgorithm(const std::string& key, const std::string& name);
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
// continuous-only algorithm asked to handle a Discrete action space, or a
// state-based one given obs=pixels envs).
void CheckAlgorithmEnvs(const AgentConfig& agent, const EnvFacts& facts, const TaskSet& tasks);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_ALGORITHMS_H_
