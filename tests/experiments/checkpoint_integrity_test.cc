// The checkpoint integrity checks on damaged and hostile state.json files:
// every single flipped bit is found (or changes nothing), and a state.json
// whose checksum matches but whose records are nonsense is a damaged
// checkpoint, never an exception of another type, undefined behaviour, a
// stack overflow or a read outside the checkpoint. The hostile cases are the
// fuzz_checkpoint findings (fuzz/checkpoint_fuzz.cc, docs/reliability.md).
#include "manyworlds/experiments/run/checkpoint_integrity.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

void Write(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
  ASSERT_TRUE(out.good()) << file;
}

std::string Read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A run directory with two sealed checkpoints, step 1 and step 2.
class CheckpointIntegrityTest : public ::testing::Test {
 protected:
  void SetUp() override {
    run_ = fs::temp_directory_path() /
           ("mw_checkpoint_integrity_test_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(run_);
    step1_ = run_ / "checkpoints" / "step_000000000001";
    step2_ = run_ / "checkpoints" / "step_000000000002";
    fs::create_directories(step1_);
    fs::create_directories(step2_);
    Write(run_ / "config.yaml", "experiment:\n  steps_per_task: 100\n");
    Write(run_ / "tasks.json", "{\"env\": \"point-nav\"}");
    for (const fs::path& dir : {step1_, step2_}) {
      Write(dir / "learner.pt", std::string(300, 'L'));
      Write(dir / "replay.bin", "replay rows");
      nlohmann::json state = {{"format", "manyworlds-train-checkpoint"},
                              {"step", dir == step1_ ? 1 : 2},
                              {"last_eval", {{"per_task", {{"a", {{"return", 0.5}}}}}}}};
      SealCheckpointState(dir, run_, state);
      Write(dir / "state.json", state.dump(2));
    }
  }
  void TearDown() override { fs::remove_all(run_); }

  // Writes `state` as step 2's state.json with the checksum a program would
  // give it (a CRC is no defence against an edit made on purpose).
  void WriteResealed(nlohmann::json state) {
    state.erase("checksum");
    const std::string dump = state.dump();
    state["checksum"] = static_cast<uint32_t>(crc32(crc32(0L, Z_NULL, 0),
                                                    reinterpret_cast<const Bytef*>(dump.data()),
                                                    static_cast<uInt>(dump.size())));
    Write(step2_ / "state.json", state.dump());
  }
  nlohmann::json Step2State() const { return nlohmann::json::parse(Read(step2_ / "state.json")); }

  fs::path run_, step1_, step2_;
};

TEST_F(CheckpointIntegrityTest, IntactCheckpointsPass) {
  EXPECT_EQ(CheckpointProblem(step2_), std::nullopt);
  EXPECT_NO_THROW(VerifyCheckpoint(step2_, run_));
  const ChosenCheckpoint chosen = ChooseCheckpoint(run_);
  EXPECT_EQ(chosen.dir, step2_);
  EXPECT_TRUE(chosen.warnings.empty());
}

// One flipped bit anywhere in state.json is reported, unless the file still
// says the same (e.g. 'e' and 'E' in an exponent). Before the fix a bit in
// the word "checksum" turned every check off: the state was taken for one
// written before the checks existed.
TEST_F(CheckpointIntegrityTest, EverySingleBitFlipOfStateJsonIsFoundOrHarmless) {
  const std::string original = Read(step2_ / "state.json");
  const nlohmann::json parsed = nlohmann::json::parse(original);
  int found = 0;
  for (size_t i = 0; i < original.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      std::string damaged = original;
      damaged[i] = static_cast<char>(damaged[i] ^ (1 << bit));
      Write(step2_ / "state.json", damaged);
      if (CheckpointProblem(step2_)) {
        ++found;
        continue;
      }
      const nlohmann::json reread = nlohmann::json::parse(damaged, nullptr, false);
      EXPECT_EQ(reread, parsed) << "byte " << i << " bit " << bit << " ('" << original[i]
                                << "') changed state.json unnoticed";
    }
  }
  EXPECT_GT(found, static_cast<int>(original.size()) * 7);
}

TEST_F(CheckpointIntegrityTest, ACheckpointWithoutAnyRecordIsAcceptedUnchecked) {
  // written before the checks existed
  Write(step2_ / "state.json", R"({"format": "manyworlds-train-checkpoint", "step": 2})");
  EXPECT_EQ(CheckpointProblem(step2_), std::nullopt);
  // but records without a checksum are a damaged seal
  Write(step2_ / "state.json", R"({"step": 2, "files": {}})");
  EXPECT_NE(CheckpointProblem(step2_), std::nullopt);
}

// Records that a matching checksum vouches for but that make no sense: each
// is a damaged checkpoint. Before the fix: nlohmann type_error escaped
// CheckpointProblem (a string or an object where a number belongs),
// UBSan reported float-to-integer overflow (1e300 bytes, a crc32 of 1e110),
// and names with a path made it read outside the checkpoint (a name of
// "/dev/zero" never returned).
TEST_F(CheckpointIntegrityTest, HostileRecordsAreDamageNotCrashes) {
  const nlohmann::json sealed = Step2State();
  struct Case {
    const char* what;
    const char* pointer;  // where in state.json
    nlohmann::json value;
  };
  const std::vector<Case> cases = {
      {"entry is a number", "/files/learner.pt", 5},
      {"bytes is a string", "/files/learner.pt/bytes", "300"},
      {"bytes is null", "/files/learner.pt/bytes", nullptr},
      {"bytes too large for int64", "/files/learner.pt/bytes", 1e300},
      {"bytes negative", "/files/learner.pt/bytes", -1},
      {"bytes a fraction", "/files/learner.pt/bytes", 300.5},
      {"crc32 too large", "/files/learner.pt/crc32", 1.08981e110},
      {"crc32 over 32 bits", "/files/learner.pt/crc32", 4294967296ULL},
      {"crc32 missing", "/files/learner.pt", {{"bytes", 300}}},
      {"files not an object", "/files", nlohmann::json::array()},
      {"a device", "/files/~1dev~1zero", {{"bytes", 1}, {"crc32", 1}}},
      {"a parent path", "/files/..~1..~1config.yaml", {{"bytes", 1}, {"crc32", 1}}},
      {"the parent directory", "/files/..", {{"bytes", 1}, {"crc32", 1}}},
      {"an empty name", "/files/", {{"bytes", 1}, {"crc32", 1}}},
      {"run_files not an object", "/run_files", "config.yaml"},
      {"a run file path", "/run_files/..~1..~1..~1etc~1passwd", 1},
      {"a run file CRC that is a string", "/run_files/config.yaml", "1"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    nlohmann::json state = sealed;
    state[nlohmann::json::json_pointer(c.pointer)] = c.value;
    WriteResealed(state);
    std::optional<std::string> problem;
    ASSERT_NO_THROW(problem = CheckpointProblem(step2_));
    ASSERT_TRUE(problem.has_value());
    EXPECT_THROW(VerifyCheckpoint(step2_, run_), Error);
    const ChosenCheckpoint chosen = ChooseCheckpoint(run_);
    EXPECT_EQ(chosen.dir, step1_);
    ASSERT_EQ(chosen.warnings.size(), 1u);
    EXPECT_NE(chosen.warnings[0].find("step_000000000002"), std::string::npos);
  }
}

// A checkpoint's file (or state.json itself) that is a pipe is never opened:
// opening or reading it would wait for a writer forever.
TEST_F(CheckpointIntegrityTest, PipesAreNotRead) {
  ASSERT_EQ(mkfifo((step2_ / "pipe").c_str(), 0600), 0);
  nlohmann::json state = Step2State();
  state["files"]["pipe"] = {{"bytes", 0}, {"crc32", 0}};
  WriteResealed(state);
  const std::optional<std::string> problem = CheckpointProblem(step2_);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("pipe"), std::string::npos) << *problem;

  fs::remove(step2_ / "state.json");
  ASSERT_EQ(mkfifo((step2_ / "state.json").c_str(), 0600), 0);
  EXPECT_NE(CheckpointProblem(step2_), std::nullopt);
  EXPECT_EQ(ChooseCheckpoint(run_).dir, step1_);
}

// 200,000 nested arrays: parsed fine, but copying or dumping the tree
// recursed once per level and overflowed the stack (found by hand with the
// fuzz harness; its inputs are capped at 4 KiB).
TEST_F(CheckpointIntegrityTest, DeeplyNestedStateIsDamageNotAStackOverflow) {
  const int depth = 200000;
  Write(step2_ / "state.json",
        "{\"checksum\": 1, \"a\": " + std::string(depth, '[') + std::string(depth, ']') + "}");
  const std::optional<std::string> problem = CheckpointProblem(step2_);
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("deeper"), std::string::npos) << *problem;
  EXPECT_EQ(ChooseCheckpoint(run_).dir, step1_);
  // a trainer's nesting is fine
  Write(step2_ / "state.json", "{\"a\": " + std::string(10, '[') + std::string(10, ']') + "}");
  EXPECT_EQ(CheckpointProblem(step2_), std::nullopt);
}

// CheckRunFiles alone (as resume calls it after CheckpointProblem) never
// reads a path a state.json names.
TEST_F(CheckpointIntegrityTest, RunFileNamesWithAPathAreRefused) {
  nlohmann::json state = Step2State();
  state["run_files"]["../../../../dev/zero"] = 1;
  WriteResealed(state);
  EXPECT_THROW(CheckRunFiles(step2_, run_), Error);
}

}  // namespace
}  // namespace manyworlds::experiments
