// What the Trainer drives: one algorithm family's loop around a learner.
// The Trainer owns the schedule, evaluation, logs, run directory and
// checkpoints and knows no algorithm; an Algorithm runs whole rounds on the
// Collector (so every iteration ends where all envs start new episodes, the
// invariant that makes resume exact) and saves everything it reads.
//   off_policy.cc  SAC family: act, store transitions, replay updates per step
//   on_policy.cc   PPO, TRPO: rollout_rounds rounds into a rollout buffer, one update
//   pearl_loop.cc  PEARL: prior and posterior rounds per task, per-task replay updates
#ifndef MANYWORLDS_EXPERIMENTS_ALGORITHM_H_
#define MANYWORLDS_EXPERIMENTS_ALGORITHM_H_

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "manyworlds/agents/actor.h"
#include "manyworlds/experiments/loops/collector.h"
#include "manyworlds/experiments/train_config.h"

namespace manyworlds::experiments {

// Streams of experiment.seed the family loops derive their generators from
// (unchanged since the first trainer, so runs keep their numbers).
inline constexpr uint64_t kAgentStream = 0x6167656e74;     // "agent"
inline constexpr uint64_t kActionStream = 0x616374696f6e;  // "action"
inline constexpr uint64_t kReplayStream = 0x7265706c6179;  // "replay"

// Seconds of a steady-clock duration (the loops' timing fields).
inline double Seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

struct AlgorithmSetup {
  const TrainConfig& config;
  const EnvFacts& facts;
  const TaskSet& tasks;
  int64_t num_tasks = 0;
  int64_t num_envs = 0;
  int64_t round_length = 0;  // env steps of one round (the longest episode)
};

class Algorithm {
 public:
  virtual ~Algorithm() = default;
  virtual int64_t rounds_per_iteration() const = 0;
  // Whether its trials have support and query rounds, so that it can train
  // on tasks with a support/query split (TaskSet::has_split).
  virtual bool SupportsSplit() const { return false; }
  // Runs rounds [first_round, first_round + rounds_per_iteration()) starting
  // at `step` env steps per env; returns the metrics row fields it adds
  // (losses, train_return, train_success, timings, ...).
  virtual nlohmann::json TrainIteration(Collector& collector, int64_t first_round,
                                        int64_t step) = 0;
  // The policy for evaluation (deterministic mode) and rollouts.
  virtual agents::Actor& actor() = 0;
  virtual int64_t updates() const = 0;
  // Writes the algorithm's files into a checkpoint directory and its
  // counters into `state` (state.json); Load reverses both. LoadPolicy reads
  // only what actor() needs.
  virtual void Save(const std::filesystem::path& dir, nlohmann::json& state) const = 0;
  virtual void Load(const std::filesystem::path& dir, const nlohmann::json& state) = 0;
  virtual void LoadPolicy(const std::filesystem::path& dir) = 0;
};

// Builds the algorithm agent.algo names (algorithms.h), after
// CheckAlgorithmEnvs. Throws ConfigError on a config it cannot run.
std::unique_ptr<Algorithm> MakeAlgorithm(const AlgorithmSetup& setup);

// The algorithm of a config set up for a task set (the same construction for
// training, evaluating a checkpoint and benchmarking collection).
std::unique_ptr<Algorithm> BuildAlgorithm(const TrainConfig& config, const TaskSet& tasks,
                                          const EnvFacts& facts);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_ALGORITHM_H_
