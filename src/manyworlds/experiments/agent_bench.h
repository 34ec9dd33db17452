// Agent update benchmarks (`manyworlds bench agent`): one function per
// algorithm, named by its registry row (algorithms.cc), timing the
// algorithm's update on random data of the given sizes.
#ifndef MANYWORLDS_EXPERIMENTS_AGENT_BENCH_H_
#define MANYWORLDS_EXPERIMENTS_AGENT_BENCH_H_

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/policy_gradient/policy_gradient.h"

namespace manyworlds::experiments {

// The sizes and settings of an agent benchmark (the flags of `bench agent`;
// each algorithm reads the ones its --help names).
struct AgentBenchSizes {
  int batch = 128;
  int minibatch = 1000;
  int hidden = 400;
  int layers = 3;
  int obs_dim = 39;
  int action_dim = 4;
  int tasks = 1;
  int trial_length = 200;  // rl2, maml: steps per trial
  int frame = 84;          // pixel learners: frames of frame x frame
  int channels = 9;        // pixel learners: channels (3 stacked RGB frames)
  std::string architecture = "mlp";
  bool pcgrad = false;
  bool gradnorm = false;
  bool disentangled_alpha = false;
  int updates = 20;
  int repeats = 5;
  int shards = 1;
  int update_threads = 0;  // 0: one per shard, at most one per core
  int torch_threads = 0;   // 0: the learner's default (nn::ConfigureTorchThreads)
  int blas_threads = 0;    // 0: the BLAS default (OPENBLAS_NUM_THREADS or one per core)
  uint64_t seed = 0;
};

struct AgentBenchResult {
  nlohmann::json json;  // sizes, unit, median rate, every repeat, threads
  std::string summary;  // human lines, ending in a newline
};

// (registry name, sizes) -> result.
using AgentBench = AgentBenchResult (*)(const std::string& algo, const AgentBenchSizes& sizes);

AgentBenchResult BenchSacUpdates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchPpoUpdates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchTrpoUpdates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchTePpoUpdates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchRl2Updates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchMamlUpdates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchPearlUpdates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchDistralUpdates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchSacAeUpdates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchDeepMdpUpdates(const std::string& algo, const AgentBenchSizes& sizes);
AgentBenchResult BenchHipBmdpUpdates(const std::string& algo, const AgentBenchSizes& sizes);

// ConfigError (CheckMemoryEstimate) if an update on `rows` rows at these
// sizes cannot fit in memory; called before a learner is built.
void CheckBenchMemory(const AgentBenchSizes& sizes, double rows);

// Any on-policy learner's whole Update on a random one-step rollout of
// --batch envs (samples per second), for `learner` built by the caller
// (after CheckBenchMemory).
AgentBenchResult TimeOnPolicyUpdates(const std::string& algo, const AgentBenchSizes& sizes,
                                     agents::OnPolicyLearner& learner, const std::string& unit);
agents::PolicySpaces BenchSpaces(const AgentBenchSizes& sizes);

// The bench of an on-policy algorithm without one of its own: its default
// config (seeded, with --hidden and --layers where it has those keys), one
// whole Update per unit. A new algorithm's registry row can name
// &BenchOnPolicyUpdates<MyLearner, MyConfig>.
template <class Learner, class Config>
AgentBenchResult BenchOnPolicyUpdates(const std::string& algo, const AgentBenchSizes& sizes) {
  CheckBenchMemory(sizes, sizes.batch);
  Config c;
  c.seed = sizes.seed;
  if constexpr (requires { c.hidden_dim; }) c.hidden_dim = sizes.hidden;
  if constexpr (requires { c.num_layers; }) c.num_layers = sizes.layers;
  Learner learner(c, BenchSpaces(sizes));
  return TimeOnPolicyUpdates(algo, sizes, learner, "one update (the config's defaults)");
}

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_AGENT_BENCH_H_
