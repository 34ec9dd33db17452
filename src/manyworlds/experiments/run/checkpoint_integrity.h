// Integrity of checkpoints. Every checkpoint's state.json records the size
// and CRC-32 (zlib) of each file beside it, the CRC-32 of the run files it
// was trained with (config.yaml, tasks.json, eval_tasks.json) and a CRC-32
// of its own content, so a flipped bit, a truncated file, an edited
// state.json or a changed config.yaml is found before anything is loaded.
// Checkpoints written before these fields existed are accepted unchecked.
#ifndef MANYWORLDS_EXPERIMENTS_RUN_CHECKPOINT_INTEGRITY_H_
#define MANYWORLDS_EXPERIMENTS_RUN_CHECKPOINT_INTEGRITY_H_

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace manyworlds::experiments {

// Adds "files", "run_files" and "checksum" to `state` for the files now in
// `checkpoint_dir` (all but state.json) and the run files of `run_dir`.
// Throws Error naming a file that cannot be read.
void SealCheckpointState(const std::filesystem::path& checkpoint_dir,
                         const std::filesystem::path& run_dir, nlohmann::json& state);

// What is wrong with a checkpoint directory ("learner.pt: 1234 bytes,
// expected 5678"), or nothing if it is intact (or predates the checks).
std::optional<std::string> CheckpointProblem(const std::filesystem::path& checkpoint_dir);

// Throws Error if the run files differ from those `checkpoint_dir` recorded:
// the run was edited or damaged, so no checkpoint of it can be trusted.
void CheckRunFiles(const std::filesystem::path& checkpoint_dir,
                   const std::filesystem::path& run_dir);

// A run's checkpoints are directories kCheckpointPrefix + the zero-padded
// step inside RUN_DIR/kCheckpointsDir.
inline constexpr char kCheckpointsDir[] = "checkpoints";
inline constexpr char kCheckpointPrefix[] = "step_";

// "step_000000012345".
std::string CheckpointName(int64_t step);

// The checkpoint directories (step_*) of a run, oldest first; none if the
// run has no checkpoints/ directory.
std::vector<std::filesystem::path> ListCheckpoints(const std::filesystem::path& run_dir);

struct ChosenCheckpoint {
  std::filesystem::path dir;
  // One line per newer checkpoint that was damaged and skipped.
  std::vector<std::string> warnings;
};

// The newest intact checkpoint of a run (highest step_*), skipping damaged
// ones with a warning each. Throws ConfigError if the run has no checkpoint
// (or checkpoints/ is not a directory), Error if none is intact or the run
// files changed.
ChosenCheckpoint ChooseCheckpoint(const std::filesystem::path& run_dir);

// Throws Error naming the problem if `checkpoint_dir` is damaged or the run
// files changed (for a checkpoint the user named).
void VerifyCheckpoint(const std::filesystem::path& checkpoint_dir,
                      const std::filesystem::path& run_dir);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_RUN_CHECKPOINT_INTEGRITY_H_
