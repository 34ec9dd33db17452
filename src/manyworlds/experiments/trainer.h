// Training runs for every algorithm family, with evaluation, logs and exact
// checkpoints. The Trainer knows no algorithm: agent.algo picks one from the
// registry (algorithms.h), and the Trainer drives it (algorithm.h) on a
// Collector (collector.h) iteration by iteration.
//
//   Trainer trainer = Trainer::Create(config);      // new run directory
//   Trainer trainer = Trainer::Resume("runs/x");    // continue the latest checkpoint
//   TrainSummary s = trainer.Run(callbacks);
//
// The schedule. Every task has envs_per_task envs, all stepped together by
// one batched executor. Training runs in rounds of one episode length: at
// the start of round r every env is re-seeded from (seed, r, env) and reset
// on a variation of its task drawn from the same stream. An iteration is one
// round (off-policy: act, store, update every step) or agent.rollout_rounds
// rounds (on-policy: collect, then one update). After an iteration: one
// metrics row; an evaluation (the multi-task protocol, evaluator.h) and a
// checkpoint when due.
//
// Exact resume. A checkpoint is taken at an iteration boundary, where every
// env is about to be re-seeded and reset, so the env state to save is nothing
// but the round number; the algorithm saves everything else it reads
// (networks, optimizers, generators, replay). A resumed run therefore
// continues with the same numbers as one never stopped; metrics rows written
// after the checkpoint by the stopped process are dropped and written again.
//
// The run directory and its checkpoints: run_dir.h.
//
// The trainer prints nothing; the caller gets progress through callbacks.
#ifndef MANYWORLDS_EXPERIMENTS_TRAINER_H_
#define MANYWORLDS_EXPERIMENTS_TRAINER_H_

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "manyworlds/experiments/evaluation/checkpoint_evaluation.h"
#include "manyworlds/experiments/evaluation/evaluator.h"
#include "manyworlds/experiments/evaluation/meta_test_protocol.h"
#include "manyworlds/experiments/run/run_dir.h"
#include "manyworlds/experiments/train_config.h"

namespace manyworlds::experiments {

struct TrainProgress {
  int64_t step = 0;         // env steps per training env so far
  int64_t total_steps = 0;  // the step the run ends at
  int64_t updates = 0;
  double elapsed_s = 0.0;        // wall time of the run, over all sessions
  double env_steps_per_s = 0.0;  // all envs, this session
  double updates_per_s = 0.0;    // this session
  std::optional<EvalResult> last_eval;
};

struct TrainCallbacks {
  std::function<void(const TrainProgress&)> on_round;    // after every round
  std::function<void(const EvalResult&)> on_eval;        // after every evaluation
  std::function<void(const std::filesystem::path&)> on_checkpoint;
  // Stop (as if killed) after the first checkpoint at or past this step;
  // the run can be continued with Resume.
  std::optional<int64_t> stop_after_step;
  // Polled after every iteration: true stops the run there, after a
  // checkpoint (a signal handler's flag, a time budget).
  std::function<bool()> stop_requested;
};

struct TrainSummary {
  bool finished = false;  // false if stopped by stop_after_step
  int64_t step = 0;
  int64_t updates = 0;
  double wall_s = 0.0;
  double env_steps_per_s = 0.0;
  double updates_per_s = 0.0;
  std::optional<EvalResult> final_eval;
  // The last meta-test (MetaTestResult::ToJson) of runs with an eval_env,
  // and the last meta-train: the same protocol on the training tasks
  // (Meta-World's "meta-train success": after adaptation).
  std::optional<nlohmann::json> final_meta_test;
  std::optional<nlohmann::json> final_meta_train;
  nlohmann::json ToJson() const;
};

// Runs `work` (a command that builds or trains learners): an allocation that fails inside
// (libtorch's "not enough memory", std::bad_alloc) becomes one Error line that says how much was
// asked and names the settings that size memory, instead of libtorch's 30-frame backtrace.
void NameMemorySettingsOnFailure(const std::function<void()>& work);

class Trainer {
 public:
  // A new run: validates the config, resolves the tasks, creates run_dir and
  // writes config.yaml and tasks.json. Throws ConfigError on a bad config or
  // if run_dir already holds a run (resume it or choose another).
  static Trainer Create(const TrainConfig& config);
  // Continues a run from its newest intact checkpoint (damaged newer ones
  // are skipped, each with a line in warnings()). Throws ConfigError if
  // run_dir is not a run or has no checkpoint to continue from, Error if
  // none is intact or the run files changed. restart: the run has no
  // intact checkpoint (it stopped before its first, or all are damaged);
  // train it again from step 0 with its saved config, keeping whatever was
  // in checkpoints/ as checkpoints.damaged.N/ (a ConfigError if an intact
  // checkpoint exists: resume that instead).
  static Trainer Resume(const std::filesystem::path& run_dir, bool restart = false);

  Trainer(Trainer&&) noexcept;
  Trainer& operator=(Trainer&&) noexcept;
  ~Trainer();

  // Trains to experiment.steps_per_task (or stop_after_step), evaluating and
  // checkpointing when due; writes summary.json when finished.
  TrainSummary Run(const TrainCallbacks& callbacks = {});

  const TrainConfig& config() const;
  const TaskSet& tasks() const;
  int64_t step() const;
  const std::filesystem::path& run_dir() const;
  // What Resume found wrong but could work around (damaged checkpoints).
  const std::vector<std::string>& warnings() const;

 private:
  struct Impl;
  explicit Trainer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace manyworlds::experiments

#endif  // MANYWORLDS_EXPERIMENTS_TRAINER_H_
