// A training run's directory: its file names, the order a new run is created
// in, its lock, and its checkpoints (written atomically, listed, read back,
// chosen with checkpoint_integrity.h) with the thread record that decides
// whether a checkpoint resumes exactly. The Trainer (trainer.h) drives runs;
// everything that reads or writes a run directory's files is here.
//
//   config.yaml              resolved configuration (written last on creation:
//                            a directory is a run once it has one)
//   tasks.json               the tasks and their task states
//   eval_tasks.json          the held-out tasks (runs with an eval_env)
//   metrics.jsonl / .csv     one row per iteration (run_log.h)
//   eval.jsonl / .csv        one row per evaluation
//   checkpoints/step_<N>/    state.json (counters, algo, threads, checksums) and
//                            the algorithm's files (written into .tmp_step_<N>/,
//                            synced, then renamed)
//   checkpoints/latest       name of the newest complete checkpoint
//   summary.json             final evaluation, wall time, rates (when finished)
#ifndef MANYWORLDS_EXPERIMENTS_RUN_RUN_DIR_H_
#define MANYWORLDS_EXPERIMENTS_RUN_RUN_DIR_H_

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "manyworlds/experiments/run/checkpoint_integrity.h"
#include "manyworlds/experiments/run/run_lock.h"
#include "manyworlds/experiments/task_set.h"
#include "manyworlds/experiments/train_config.h"

namespace manyworlds::experiments {

// Names inside a run directory.
struct RunPaths {
  std::filesystem::path dir;
  std::filesystem::path config() const { return dir / "config.yaml"; }
  std::filesystem::path tasks() const { return dir / "tasks.json"; }
  // The held-out tasks of the meta-test (runs with an eval_env only).
  std::filesystem::path eval_tasks() const { return dir / "eval_tasks.json"; }
  std::filesystem::path checkpoints() const { return dir / kCheckpointsDir; }
  std::filesystem::path summary() const { return dir / "summary.json"; }
};

// A resolved run read back from its directory: config and tasks. Throws
// ConfigError if the directory is not a run.
struct RunInfo {
  TrainConfig config;
  TaskSet tasks;
  std::optional<TaskSet> eval_tasks;  // eval_tasks.json, if the run has an eval_env
  static RunInfo Read(const std::filesystem::path& run_dir);
};

// The step a finished run ended at: its summary.json (a regular file of at
// most 64 MiB) parses and says "finished": true with an integer "step".
// Otherwise (no summary, unfinished, unreadable) none; never throws.
std::optional<int64_t> FinishedRunStep(const std::filesystem::path& run_dir);

// Throws ConfigError if run_dir already holds a run (config.yaml, or a
// non-empty checkpoints/), naming how to continue it.
void RefuseExistingRun(const std::filesystem::path& run_dir);

// Creates a new run's directory in the order that makes a kill at any point
// harmless: the directory, its lock (the check repeated under it, so of two
// processes started together one is refused), eval_tasks.json, tasks.json, an
// empty checkpoints/ (a run that has not reached its first checkpoint), then
// config.yaml. Returns the lock, held while the run is written.
std::unique_ptr<RunLock> CreateRunDirectory(const std::filesystem::path& run_dir,
                                            const TrainConfig& config, const TaskSet& tasks,
                                            const std::optional<TaskSet>& eval_tasks);

// Removes what a killed writer left behind: hidden `.NAME.tmp.XXXXXX` files
// (AtomicWriteFile) in the run and checkpoint directories and partial
// `.tmp_step_*` checkpoints. Only under the run's lock: no writer is alive.
void RemoveStaleTemporaries(const std::filesystem::path& run_dir);

// CheckpointName and ListCheckpoints: checkpoint_integrity.h (it needs no
// more than the file system, so the fuzzer builds it alone).

// Writes a checkpoint of `step`: `write_files(dir, state)` writes the
// algorithm's files into a temporary directory and adds its counters to
// `state`; then state.json is sealed with checksums (checkpoint_integrity.h),
// every file synced, the directory renamed to step_<N> and `latest` updated.
// Keeps the newest `keep` checkpoints (0: all). A failed write (full disk,
// I/O error) removes the partial checkpoint and throws, leaving the previous
// one as the newest. Returns the checkpoint's directory.
std::filesystem::path WriteCheckpoint(
    const std::filesystem::path& run_dir, int64_t step, int64_t keep, nlohmann::json state,
    const std::function<void(const std::filesystem::path& dir, nlohmann::json& state)>&
        write_files);

// state.json of a checkpoint; Error naming the file if it is unreadable.
nlohmann::json ReadCheckpointState(const std::filesystem::path& checkpoint);

// The step a checkpoint was taken at; Error naming the file if unreadable.
int64_t CheckpointStep(const std::filesystem::path& checkpoint);

// The newest intact checkpoint of a run (ChooseCheckpoint without the
// warnings). Throws ConfigError if the run has none, Error if none is intact.
std::filesystem::path LatestCheckpoint(const std::filesystem::path& run_dir);

// The thread counts a product's rounding depends on, as a checkpoint records
// them ({torch_intra_op, blas_threads, blas_core}).
nlohmann::json ThreadRecord();

// "checkpoint 'D' was written with B BLAS thread(s) and T torch thread(s);
// this process has ..." where a checkpoint's thread record differs from this
// process's counts; nothing when they agree.
std::optional<std::string> ThreadCountMismatch(const std::filesystem::path& checkpoint,
                                               const nlohmann::json& record);

// Where a checkpoint was written with other BLAS or torch thread counts than
// this process has, a warning for `eval`: the products round differently, so
// its numbers need not match the run's own evaluations (resume refuses such a
// checkpoint instead). Nothing when the counts agree, for older checkpoints
// without a thread record, and for unreadable ones (the evaluation says why).
std::optional<std::string> EvaluationThreadWarning(const std::filesystem::path& checkpoint);

// Makes a written file (or a directory's entries) durable; Error naming the
// path if the kernel reports a write-back failure (EIO, ENOSPC).
void FsyncPath(const std::filesystem::path& path, bool directory);

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_RUN_RUN_DIR_H_
