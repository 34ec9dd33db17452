// A run stopped and resumed from a checkpoint gives the same metrics and
// bit-identical evaluations as one never stopped; bad run directories and
// corrupt checkpoints fail clearly without touching the logs.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "manyworlds/agents/sac/sac_config.h"
#include "manyworlds/core/error.h"
#include "manyworlds/experiments/run/checkpoint_integrity.h"
#include "manyworlds/experiments/run/run_lock.h"
#include "manyworlds/experiments/run/run_log.h"
#include "manyworlds/experiments/trainer.h"
#include "tests/experiments/scratch_dirs.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

fs::path Scratch(const std::string& name) { return test_dirs::Scratch("resume", name); }

// Three point-nav goals, two envs per task, half an update per step: small,
// but every part of the state (replay, learner, generators, variations of
// the round seeds) matters for the numbers.
TrainConfig Tiny(const fs::path& run_dir) {
  TrainConfig c;
  c.env.id = "point-nav";
  c.env.num_tasks = 3;
  c.env.envs_per_task = 2;
  c.env.options = {{"horizon", 50}};
  c.agent.as<agents::SacConfig>().hidden_dim = 32;
  c.agent.as<agents::SacConfig>().num_layers = 2;
  c.agent.as<agents::SacConfig>().batch_size = 16;
  c.agent.as<agents::SacConfig>().disentangled_alpha = true;
  c.replay.capacity = 3000;
  c.experiment.seed = 11;
  c.experiment.steps_per_task = 600;
  c.experiment.warmup_steps = 100;
  c.experiment.updates_per_step = 0.5;
  c.experiment.eval_every = 100;
  c.experiment.eval_episodes = 3;
  c.experiment.checkpoint_every = 300;
  c.experiment.keep_checkpoints = 0;
  c.experiment.run_dir = run_dir.string();
  return c;
}

// Rows without wall-clock fields.
std::vector<nlohmann::json> Rows(const fs::path& file) {
  std::vector<nlohmann::json> rows = ReadJsonLines(file);
  for (auto& row : rows) {
    for (const char* key : {"wall_s", "env_steps_per_s", "updates_per_s", "time_act_s",
                            "time_env_s", "time_update_s"}) {
      row.erase(key);
    }
  }
  return rows;
}

std::string Slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(ResumeTest, ResumedRunMatchesAnUninterruptedOne) {
  const fs::path a = Scratch("a"), b = Scratch("b"), c = Scratch("c");
  {
    Trainer full = Trainer::Create(Tiny(a));
    ASSERT_TRUE(full.Run().finished);
  }
  // b: runs to the end, then is "killed" as if just after its mid-run
  // checkpoint: the later checkpoint and the summary are lost, the logs hold
  // rows past the checkpoint, and a half-written checkpoint lies around
  {
    Trainer t = Trainer::Create(Tiny(b));
    ASSERT_TRUE(t.Run().finished);
  }
  fs::remove_all(b / "checkpoints/step_000000000600");
  fs::remove(b / "summary.json");
  fs::create_directories(b / "checkpoints/.tmp_step_000000000600");
  std::ofstream(b / "checkpoints/.tmp_step_000000000600/learner.pt") << "partial";
  std::ofstream(b / ".metrics.csv.tmp.Ab12Cd") << "half a rewrite";
  ASSERT_EQ(LatestCheckpoint(b).filename(), "step_000000000300");
  {
    Trainer resumed = Trainer::Resume(b);
    EXPECT_EQ(resumed.step(), 300);
    // what the killed writer left behind is gone
    EXPECT_FALSE(fs::exists(b / "checkpoints/.tmp_step_000000000600"));
    EXPECT_FALSE(fs::exists(b / ".metrics.csv.tmp.Ab12Cd"));
    // rows after the checkpoint are gone until the run writes them again
    EXPECT_EQ(Rows(b / "eval.jsonl").size(), 3u);
    const TrainSummary s = resumed.Run();
    EXPECT_TRUE(s.finished);
  }
  // c: stopped by stop_after_step at its first checkpoint, then resumed
  {
    Trainer t = Trainer::Create(Tiny(c));
    TrainCallbacks callbacks;
    callbacks.stop_after_step = 1;
    EXPECT_FALSE(t.Run(callbacks).finished);
    EXPECT_EQ(t.step(), 300);
  }
  {
    Trainer resumed = Trainer::Resume(c);
    EXPECT_TRUE(resumed.Run().finished);
  }

  const auto eval_a = Rows(a / "eval.jsonl");
  ASSERT_EQ(eval_a.size(), 6u);
  EXPECT_EQ(Rows(a / "metrics.jsonl").size(), 12u);  // 600 steps / 50 per round
  for (const fs::path& other : {b, c}) {
    SCOPED_TRACE(other.string());
    EXPECT_EQ(Rows(other / "eval.jsonl"), eval_a);  // bit-identical numbers
    EXPECT_EQ(Rows(other / "metrics.jsonl"), Rows(a / "metrics.jsonl"));
    // the final networks and replay are identical too
    EXPECT_EQ(Slurp(other / "checkpoints/step_000000000600/replay.bin"),
              Slurp(a / "checkpoints/step_000000000600/replay.bin"));
    EXPECT_TRUE(fs::exists(other / "summary.json"));
    EXPECT_TRUE(fs::exists(other / "metrics.csv"));
    EXPECT_TRUE(fs::exists(other / "eval.csv"));
  }
  // the evaluation of a checkpoint reproduces the one logged in training
  const EvalResult again =
      EvaluateCheckpoint(RunInfo::Read(a), LatestCheckpoint(a), 3);
  nlohmann::json again_json = again.ToJson();
  again_json.erase("wall_s");
  EXPECT_EQ(again_json, eval_a.back());
  // a finished run resumes to nothing
  {
    Trainer done = Trainer::Resume(a);
    const TrainSummary s = done.Run();
    EXPECT_TRUE(s.finished);
    EXPECT_EQ(Rows(a / "eval.jsonl"), eval_a);
  }
  for (const auto& d : {a, b, c}) fs::remove_all(d);
}

TEST(ResumeTest, ARunDirectoryHasOneWriterAtATime) {
  const fs::path dir = Scratch("locked");
  auto message = [](const std::function<void()>& f) -> std::string {
    try {
      f();
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  {
    // another process still creating the run (here: a second open of the
    // lock) holds it: this one is refused and told who holds it
    fs::create_directories(dir);
    const RunLock creating(dir);
    const std::string create = message([&] { Trainer::Create(Tiny(dir)); });
    EXPECT_NE(create.find("in use by another manyworlds process (pid " +
                          std::to_string(getpid()) + ")"),
              std::string::npos)
        << create;
    EXPECT_FALSE(fs::exists(dir / "config.yaml"));
  }
  {
    Trainer first = Trainer::Create(Tiny(dir));
    EXPECT_NE(message([&] { Trainer::Resume(dir); }).find("in use"), std::string::npos);
  }
  // released with the trainer: the run (stopped before its first
  // checkpoint) may be trained again
  EXPECT_NO_THROW(Trainer::Resume(dir, /*restart=*/true));
  fs::remove_all(dir);

  // killed before config.yaml was written (checkpoints/ already made): not a
  // run yet, so train may start it again
  const fs::path half = Scratch("half_created");
  fs::create_directories(half / "checkpoints");
  std::ofstream(half / "tasks.json") << "{}";
  EXPECT_NO_THROW(Trainer::Create(Tiny(half)));
  EXPECT_TRUE(fs::exists(half / "config.yaml"));
  fs::remove_all(half);
}

TEST(ResumeTest, ARunKilledBeforeItsFirstCheckpointResumesFromStepZero) {
  const fs::path whole = Scratch("whole_run");
  const fs::path cut = Scratch("cut_run");
  {
    Trainer t = Trainer::Create(Tiny(whole));
    ASSERT_TRUE(t.Run().finished);
  }
  {
    // created, then killed before the first checkpoint (here: dropped)
    Trainer t = Trainer::Create(Tiny(cut));
    EXPECT_TRUE(fs::is_directory(cut / "checkpoints"));
  }
  {
    Trainer t = Trainer::Resume(cut);
    EXPECT_EQ(t.step(), 0);
    ASSERT_EQ(t.warnings().size(), 1u);
    EXPECT_NE(t.warnings()[0].find("before its first checkpoint"), std::string::npos);
    ASSERT_TRUE(t.Run().finished);
  }
  EXPECT_EQ(Rows(cut / "metrics.jsonl"), Rows(whole / "metrics.jsonl"));
  EXPECT_FALSE(fs::exists(cut / "checkpoints.damaged.1"));
  fs::remove_all(whole);
  fs::remove_all(cut);
}

TEST(ResumeTest, BadRunsFailClearlyAndLoseNothing) {
  const fs::path dir = Scratch("bad");
  EXPECT_THROW(Trainer::Resume(dir), ConfigError);  // missing
  fs::create_directories(dir);
  EXPECT_THROW(Trainer::Resume(dir), ConfigError);  // not a run
  fs::remove_all(dir);

  TrainConfig config = Tiny(dir);
  config.experiment.steps_per_task = 300;
  {
    Trainer t = Trainer::Create(config);
    t.Run();
  }
  // a second Create would overwrite the run
  EXPECT_THROW(Trainer::Create(config), ConfigError);

  const std::string metrics = Slurp(dir / "metrics.jsonl");
  const fs::path learner = dir / "checkpoints/step_000000000300/learner.pt";
  const std::string original = Slurp(learner);
  std::string bytes = original;
  bytes.resize(bytes.size() / 2);
  std::ofstream(learner, std::ios::binary | std::ios::trunc) << bytes;
  try {
    Trainer::Resume(dir);
    ADD_FAILURE() << "a corrupt checkpoint resumed";
  } catch (const ConfigError& e) {
    ADD_FAILURE() << "corrupt checkpoint reported as a config error: " << e.what();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("learner.pt"), std::string::npos) << e.what();
  }
  EXPECT_THROW(EvaluateCheckpoint(RunInfo::Read(dir), LatestCheckpoint(dir), 1), Error);
  EXPECT_EQ(Slurp(dir / "metrics.jsonl"), metrics);  // nothing lost

  std::ofstream(learner, std::ios::binary | std::ios::trunc) << original;
  fs::remove(dir / "checkpoints/step_000000000300/replay.bin");
  std::ofstream(dir / "checkpoints/step_000000000300/replay.bin") << "junk";
  try {
    Trainer::Resume(dir);
    ADD_FAILURE() << "a corrupt replay snapshot resumed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("replay.bin"), std::string::npos) << e.what();
  }
  EXPECT_EQ(Slurp(dir / "metrics.jsonl"), metrics);
  fs::remove_all(dir);
}

TEST(ResumeTest, DamagedCheckpointsAreFoundAndTheNewestIntactOneIsUsed) {
  const fs::path dir = Scratch("damage");
  {
    Trainer t = Trainer::Create(Tiny(dir));
    ASSERT_TRUE(t.Run().finished);
  }
  const fs::path newest = dir / "checkpoints/step_000000000600";
  const std::string learner = Slurp(newest / "learner.pt");
  EXPECT_FALSE(CheckpointProblem(newest));

  // one flipped bit, same size: found, and the run goes back to step 300
  std::string flipped = learner;
  flipped[flipped.size() / 2] ^= 0x10;
  std::ofstream(newest / "learner.pt", std::ios::binary | std::ios::trunc) << flipped;
  ASSERT_TRUE(CheckpointProblem(newest));
  EXPECT_NE(CheckpointProblem(newest)->find("learner.pt"), std::string::npos);
  const ChosenCheckpoint chosen = ChooseCheckpoint(dir);
  EXPECT_EQ(chosen.dir.filename(), "step_000000000300");
  ASSERT_EQ(chosen.warnings.size(), 1u);
  EXPECT_NE(chosen.warnings[0].find("step_000000000600"), std::string::npos);
  EXPECT_THROW(VerifyCheckpoint(newest, dir), Error);
  {
    Trainer resumed = Trainer::Resume(dir);
    EXPECT_EQ(resumed.step(), 300);
    EXPECT_EQ(resumed.warnings().size(), 1u);
    ASSERT_TRUE(resumed.Run().finished);
  }
  // retrained from 300, the damaged checkpoint is rewritten bit for bit
  EXPECT_EQ(Slurp(newest / "learner.pt"), learner);
  EXPECT_FALSE(CheckpointProblem(newest));
  const std::string metrics = Slurp(dir / "metrics.jsonl");

  // an edited step in state.json
  const std::string state = Slurp(newest / "state.json");
  std::string edited = state;
  const size_t at = edited.find("\"step\": 600");
  ASSERT_NE(at, std::string::npos);
  edited.replace(at, 11, "\"step\": 500");
  std::ofstream(newest / "state.json", std::ios::trunc) << edited;
  ASSERT_TRUE(CheckpointProblem(newest));
  EXPECT_NE(CheckpointProblem(newest)->find("state.json"), std::string::npos);
  EXPECT_EQ(ChooseCheckpoint(dir).dir.filename(), "step_000000000300");
  std::ofstream(newest / "state.json", std::ios::trunc) << state;

  // an empty `latest` changes nothing
  std::ofstream(dir / "checkpoints/latest", std::ios::trunc).flush();
  EXPECT_EQ(ChooseCheckpoint(dir).dir, newest);

  // a config.yaml that is not the run's: every checkpoint refuses it
  const std::string config = Slurp(dir / "config.yaml");
  std::ofstream(dir / "config.yaml", std::ios::app) << "# edited\n";
  try {
    Trainer::Resume(dir);
    ADD_FAILURE() << "an edited config.yaml resumed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("config.yaml"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LatestCheckpoint(dir), Error);
  std::ofstream(dir / "config.yaml", std::ios::trunc) << config;
  EXPECT_EQ(Slurp(dir / "metrics.jsonl"), metrics);  // nothing lost
  fs::remove_all(dir);
}

TEST(ResumeTest, AFullDiskDuringACheckpointKeepsTheLastGoodOneResumable) {
  const fs::path dir = Scratch("full");
  {
    Trainer t = Trainer::Create(Tiny(dir));
    TrainCallbacks stop;
    stop.stop_after_step = 300;
    ASSERT_FALSE(t.Run(stop).finished);
  }
  const fs::path good = dir / "checkpoints/step_000000000300";
  // no file may grow past half the learner archive (RLIMIT_FSIZE, the
  // failure a full disk gives: write() fails part-way): the logs stay far
  // below that, the next checkpoint cannot be written
  const auto limit = static_cast<rlim_t>(fs::file_size(good / "learner.pt") / 2);
  ASSERT_LT(fs::file_size(dir / "metrics.jsonl") * 4, limit);
  std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
  rlimit small = old;
  small.rlim_cur = limit;
  std::string what;
  {
    Trainer t = Trainer::Resume(dir);
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
    try {
      t.Run();
    } catch (const Error& e) {
      what = e.what();
    }
    setrlimit(RLIMIT_FSIZE, &old);
  }
  std::signal(SIGXFSZ, SIG_DFL);
  EXPECT_NE(what.find("step_000000000600"), std::string::npos) << what;
  // nothing partial is left; the last good checkpoint is the newest and intact
  EXPECT_FALSE(fs::exists(dir / "checkpoints/.tmp_step_000000000600"));
  EXPECT_FALSE(fs::exists(dir / "checkpoints/step_000000000600"));
  EXPECT_EQ(ChooseCheckpoint(dir).dir, good);
  {
    Trainer t = Trainer::Resume(dir);
    EXPECT_EQ(t.step(), 300);
    ASSERT_TRUE(t.Run().finished);
  }
  fs::remove_all(dir);
}

TEST(ResumeTest, ARunWithoutCheckpointsAsksForRestartInsteadOfRetrainingSilently) {
  const fs::path dir = Scratch("nockpt");
  {
    Trainer t = Trainer::Create(Tiny(dir));
    ASSERT_TRUE(t.Run().finished);
  }
  const std::string metrics = Slurp(dir / "metrics.jsonl");
  const std::vector<nlohmann::json> rows = Rows(dir / "metrics.jsonl");
  fs::remove_all(dir / "checkpoints");
  try {
    Trainer::Resume(dir);
    ADD_FAILURE() << "a run without checkpoints resumed";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--restart"), std::string::npos) << e.what();
  }
  // checkpoints/ as a file: the same, and nothing is truncated
  std::ofstream(dir / "checkpoints") << "not a directory";
  try {
    Trainer::Resume(dir);
    ADD_FAILURE() << "a run whose checkpoints/ is a file resumed";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("not a directory"), std::string::npos) << e.what();
  }
  EXPECT_EQ(Slurp(dir / "metrics.jsonl"), metrics);
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  // --restart trains again from step 0, keeping the stray file aside
  {
    Trainer again = Trainer::Resume(dir, /*restart=*/true);
    EXPECT_EQ(again.step(), 0);
    EXPECT_FALSE(fs::exists(dir / "summary.json"));
    EXPECT_TRUE(fs::exists(dir / "checkpoints.damaged.1"));
    ASSERT_TRUE(again.Run().finished);
  }
  EXPECT_EQ(Rows(dir / "metrics.jsonl"), rows);  // the same run again
  // with an intact checkpoint, --restart is refused
  EXPECT_THROW(Trainer::Resume(dir, /*restart=*/true), ConfigError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace manyworlds::experiments
