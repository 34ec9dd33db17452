// Evaluations of a saved policy: a checkpoint of a run evaluated with the
// multi-task protocol (evaluator.h) or the meta-test protocol
// (meta_test_protocol.h), as `manyworlds eval` and `rollout --policy
// checkpoint:` run them.
#ifndef MANYWORLDS_EXPERIMENTS_EVALUATION_CHECKPOINT_EVALUATION_H_
#define MANYWORLDS_EXPERIMENTS_EVALUATION_CHECKPOINT_EVALUATION_H_

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "manyworlds/experiments/evaluation/evaluator.h"
#include "manyworlds/experiments/evaluation/meta_test_protocol.h"
#include "manyworlds/experiments/run/run_dir.h"

namespace manyworlds::experiments {

// Evaluates the learner saved in a checkpoint directory (learner.pt) on the
// run's tasks with `episodes` per task, seeded by the run's evaluation seed
// or by `seed` when given. Throws Error on a corrupt checkpoint.
EvalResult EvaluateCheckpoint(const RunInfo& run, const std::filesystem::path& checkpoint,
                              int64_t episodes, std::optional<uint64_t> seed = std::nullopt);

// Runs the meta-test protocol (meta_test_protocol.h) with the run's
// meta_test settings on its held-out tasks, for the learner saved in a
// checkpoint directory. Throws ConfigError if the run has no eval_env
// (no held-out tasks), Error on a corrupt checkpoint.
nlohmann::json MetaTestCheckpoint(const RunInfo& run, const std::filesystem::path& checkpoint,
                                  std::optional<uint64_t> seed = std::nullopt);
// The same protocol on the run's training tasks (meta-train success, as
// logged during training). Same errors.
nlohmann::json MetaTrainCheckpoint(const RunInfo& run, const std::filesystem::path& checkpoint,
                                   std::optional<uint64_t> seed = std::nullopt);
// The same protocol with `trials` trials per held-out task instead of the
// config's trials_per_task, every episode kept (rollout of a meta-learner).
MetaTestResult MetaTestCheckpointEpisodes(const RunInfo& run,
                                          const std::filesystem::path& checkpoint, int64_t trials,
                                          uint64_t seed);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_EVALUATION_CHECKPOINT_EVALUATION_H_
