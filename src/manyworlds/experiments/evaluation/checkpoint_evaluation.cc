#include "manyworlds/experiments/evaluation/checkpoint_evaluation.h"

#include <memory>
#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"
#include "manyworlds/envs/all.h"
#include "manyworlds/experiments/algorithm.h"
#include "manyworlds/experiments/run/run_dir.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

MetaTestResult RunMetaTestOn(const RunInfo& run, const fs::path& checkpoint,
                             const MetaTestConfig& config, uint64_t seed, bool on_training_tasks) {
  if (!run.eval_tasks) {
    throw ConfigError(std::string(on_training_tasks ? "meta-train" : "meta-test") +
                      " needs held-out tasks, and this run has none: train with an "
                      "eval_env section (e.g. eval_env: {options: {split: test}} for ML1/ML10, "
                      "or eval_env: {task_seed: 1} for a sampled task distribution)");
  }
  const Registry& registry = DefaultRegistry();
  MetaTestProtocol protocol(on_training_tasks ? run.tasks : *run.eval_tasks, registry, config, seed,
                            run.config.experiment.num_threads);
  // the algorithm is built for the training tasks: their facts, read from one env each where the
  // protocol runs on the held-out ones
  const EnvFacts facts =
      on_training_tasks ? protocol.facts() : InspectEnvs(run.tasks, registry);
  if (!on_training_tasks) CheckEvalFacts(protocol.facts(), facts);
  std::unique_ptr<Algorithm> algorithm = BuildAlgorithm(run.config, run.tasks, facts);
  algorithm->LoadPolicy(checkpoint);
  MetaTestResult result = protocol.RunMetaTest(algorithm->actor());
  result.step = CheckpointStep(checkpoint);
  return result;
}

}  // namespace

nlohmann::json MetaTestCheckpoint(const RunInfo& run, const fs::path& checkpoint,
                                  std::optional<uint64_t> seed) {
  return RunMetaTestOn(run, checkpoint, run.config.meta_test,
                       seed ? *seed : MixSeed(run.config.experiment.seed, kMetaTestSeedStream),
                       /*on_training_tasks=*/false)
      .ToJson();
}

nlohmann::json MetaTrainCheckpoint(const RunInfo& run, const fs::path& checkpoint,
                                   std::optional<uint64_t> seed) {
  return RunMetaTestOn(run, checkpoint, run.config.meta_test,
                       seed ? *seed : MixSeed(run.config.experiment.seed, kMetaTrainSeedStream),
                       /*on_training_tasks=*/true)
      .ToJson();
}

MetaTestResult MetaTestCheckpointEpisodes(const RunInfo& run, const fs::path& checkpoint,
                                          int64_t trials, uint64_t seed) {
  // trials one by one, every episode shown: the per_variation protocol, with
  // metalearning_evaluation's adaptation episodes as its exploration
  MetaTestConfig config = run.config.meta_test;
  if (!config.per_variation()) config.exploration_episodes = config.adaptation_episodes;
  config.protocol = kPerVariation;
  config.trials_per_task = trials;
  return RunMetaTestOn(run, checkpoint, config, seed, /*on_training_tasks=*/false);
}

EvalResult EvaluateCheckpoint(const RunInfo& run, const fs::path& checkpoint, int64_t episodes,
                              std::optional<uint64_t> seed) {
  const Registry& registry = DefaultRegistry();
  Evaluator evaluator(run.tasks, registry, episodes,
                      seed ? *seed : MixSeed(run.config.experiment.seed, kEvalSeedStream),
                      run.config.experiment.num_threads);
  evaluator.TerminateOnSuccess(run.config.experiment.eval_terminate_on_success);
  std::unique_ptr<Algorithm> algorithm = BuildAlgorithm(run.config, run.tasks, evaluator.facts());
  algorithm->LoadPolicy(checkpoint);
  EvalResult result = evaluator.Run(algorithm->actor());
  result.step = CheckpointStep(checkpoint);
  return result;
}

}  // namespace manyworlds::experiments
