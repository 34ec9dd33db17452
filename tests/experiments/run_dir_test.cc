// The run-directory module: checkpoints are listed by step, written whole or
// not at all, pruned to the newest, and a directory that holds a run is
// never taken for a new one.
#include "manyworlds/experiments/run/run_dir.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "manyworlds/core/error.h"
#include "manyworlds/experiments/run/checkpoint_integrity.h"
#include "tests/experiments/scratch_dirs.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

fs::path Dir(const std::string& name) {
  const fs::path dir = test_dirs::Scratch("run_dir", name);
  fs::create_directories(dir);
  return dir;
}

fs::path Write(const fs::path& run, int64_t step, int64_t keep, const std::string& payload) {
  return WriteCheckpoint(run, step, keep, {{"step", step}},
                         [&](const fs::path& dir, nlohmann::json& state) {
                           std::ofstream(dir / "learner.pt") << payload;
                           state["payload"] = payload;
                         });
}

TEST(RunDirTest, CheckpointsAreListedByStepAndTheNewestIsLatest) {
  const fs::path run = Dir("list");
  EXPECT_TRUE(ListCheckpoints(run).empty());
  Write(run, 1000, 0, "b");
  Write(run, 50, 0, "a");
  Write(run, 20000, 0, "c");
  fs::create_directories(RunPaths{run}.checkpoints() / "not_a_checkpoint");
  const auto found = ListCheckpoints(run);
  ASSERT_EQ(found.size(), 3u);
  EXPECT_EQ(found[0].filename(), CheckpointName(50));
  EXPECT_EQ(found[2].filename(), CheckpointName(20000));
  EXPECT_EQ(CheckpointStep(found[1]), 1000);
  EXPECT_EQ(ReadCheckpointState(found[1]).at("payload"), "b");
  EXPECT_EQ(LatestCheckpoint(run), found[2]);
  EXPECT_FALSE(CheckpointProblem(found[2]).has_value());
  std::ifstream latest(RunPaths{run}.checkpoints() / "latest");
  std::string name;
  latest >> name;
  EXPECT_EQ(name, CheckpointName(20000));  // the last written
}

TEST(RunDirTest, KeepPrunesOlderCheckpoints) {
  const fs::path run = Dir("keep");
  for (int64_t step : {100, 200, 300}) Write(run, step, 2, "x");
  const auto found = ListCheckpoints(run);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].filename(), CheckpointName(200));
}

TEST(RunDirTest, AFailedWriteLeavesThePreviousCheckpointNewest) {
  const fs::path run = Dir("failed");
  const fs::path first = Write(run, 100, 1, "good");
  EXPECT_THROW(WriteCheckpoint(run, 200, 1, {{"step", 200}},
                               [](const fs::path&, nlohmann::json&) { throw Error("disk full"); }),
               Error);
  const auto found = ListCheckpoints(run);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0], first);
  for (const auto& entry : fs::directory_iterator(RunPaths{run}.checkpoints())) {
    EXPECT_NE(entry.path().filename().string().rfind(".tmp_", 0), 0u) << entry.path();
  }
}

TEST(RunDirTest, ADirectoryHoldingARunIsRefused) {
  const fs::path run = Dir("refuse");
  EXPECT_NO_THROW(RefuseExistingRun(run));
  fs::create_directories(RunPaths{run}.checkpoints());  // a creation cut short
  EXPECT_NO_THROW(RefuseExistingRun(run));
  std::ofstream(RunPaths{run}.config()) << "env: {id: cartpole}\n";
  try {
    RefuseExistingRun(run);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--resume"), std::string::npos) << e.what();
  }
}

TEST(RunDirTest, StaleTemporariesAreRemoved) {
  const fs::path run = Dir("stale");
  Write(run, 100, 0, "x");
  const fs::path partial = RunPaths{run}.checkpoints() / (".tmp_" + CheckpointName(200));
  fs::create_directories(partial);
  std::ofstream(run / ".metrics.jsonl.tmp.abc123") << "half";
  RemoveStaleTemporaries(run);
  EXPECT_FALSE(fs::exists(partial));
  EXPECT_FALSE(fs::exists(run / ".metrics.jsonl.tmp.abc123"));
  EXPECT_EQ(ListCheckpoints(run).size(), 1u);
}

// A reader choosing the latest checkpoint of a run that is training (keep_checkpoints 1: each
// write prunes the one before) never fails: a checkpoint pruned while it was being checked is
// chosen again (CI saw `eval` fail this way under load).
TEST(RunDirTest, ChoosingWhileATrainerWritesAndPrunesAlwaysFindsOne) {
  const fs::path run = Dir("choose_while_pruned");
  Write(run, 1, 1, std::string(4096, 'x'));
  std::atomic<bool> stop{false};
  std::thread trainer([&] {
    for (int64_t step = 2; !stop; ++step) Write(run, step, 1, std::string(4096, 'x'));
  });
  int failures = 0;
  std::string first_failure;
  for (int i = 0; i < 3000; ++i) {
    try {
      const ChosenCheckpoint chosen = ChooseCheckpoint(run);
      EXPECT_TRUE(chosen.warnings.empty()) << chosen.warnings.front();
    } catch (const std::exception& e) {
      if (failures++ == 0) first_failure = e.what();
    }
  }
  stop = true;
  trainer.join();
  EXPECT_EQ(failures, 0) << "first: " << first_failure;
}

}  // namespace
}  // namespace manyworlds::experiments
