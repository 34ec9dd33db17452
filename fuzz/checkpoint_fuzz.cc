// Any text as the state.json of a run's newest checkpoint. A run directory is
// made once in a temporary folder:
//
//   RUN/config.yaml, RUN/tasks.json
//   RUN/checkpoints/step_000000000001/  learner.pt, replay.bin, state.json (sealed, intact)
//   RUN/checkpoints/step_000000000002/  learner.pt, replay.bin, state.json = the input
//
// Input: one flag byte, then the text of state.json. Flag bit 0: if the text
// is a JSON object, its "checksum" is set to the right CRC-32 first, so that
// the fuzzer gets past the checksum to the fields it protects (a CRC is no
// defence against someone who edits state.json on purpose).
//
// Contract: CheckpointProblem returns (never throws); CheckRunFiles,
// VerifyCheckpoint and ChooseCheckpoint throw nothing but Error; and
// ChooseCheckpoint picks step 2 exactly when CheckpointProblem finds it
// intact (and its run files match), else step 1 with one warning. A hang
// (reading a device or pipe a state.json names) is a libFuzzer timeout.
//
// MANYWORLDS_FUZZ_WRITE_SEEDS=DIR writes the seed inputs (the corpus in
// tests/fuzz/corpus/checkpoint/) into DIR and exits.
#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "manyworlds/core/error.h"
#include "manyworlds/experiments/run/checkpoint_integrity.h"

namespace {

namespace fs = std::filesystem;
namespace ex = manyworlds::experiments;

void Write(const fs::path& file, std::string_view text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", file.c_str());
    std::abort();
  }
}

// The state fields a trainer writes (see Trainer::Impl::SaveCheckpoint).
nlohmann::json TrainerState(int64_t step) {
  return {{"format", "manyworlds-train-checkpoint"},
          {"version", 1},
          {"algo", "sac"},
          {"num_tasks", 2},
          {"num_envs", 2},
          {"obs_dim", 6},
          {"action_dim", 2},
          {"step", step},
          {"round", step},
          {"updates", step / 2},
          {"wall_s", 1.5},
          {"last_eval", nullptr}};
}

struct Run {
  fs::path root;
  fs::path step1, step2;

  Run() {
    char pattern[] = "/tmp/manyworlds_fuzz_checkpoint.XXXXXX";
    if (mkdtemp(pattern) == nullptr) std::abort();
    root = pattern;
    step1 = root / "checkpoints" / "step_000000000001";
    step2 = root / "checkpoints" / "step_000000000002";
    fs::create_directories(step1);
    fs::create_directories(step2);
    Write(root / "config.yaml", "experiment:\n  steps_per_task: 100\n");
    Write(root / "tasks.json", R"({"env":"point-nav","tasks":[]})");
    for (const fs::path& dir : {step1, step2}) {
      Write(dir / "learner.pt", std::string(300, 'L'));
      Write(dir / "replay.bin", "MWREPLAY and some rows");
    }
    nlohmann::json state = TrainerState(1);
    ex::SealCheckpointState(step1, root, state);
    Write(step1 / "state.json", state.dump(2));
  }
  ~Run() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }

  // A sealed state of step 2, as the trainer writes it.
  std::string SealedStep2() const {
    nlohmann::json state = TrainerState(2);
    ex::SealCheckpointState(step2, root, state);
    return state.dump(2);
  }
};

Run& TheRun() {
  static Run run;
  return run;
}

// Sets "checksum" as SealCheckpointState does: the CRC-32 of the key-sorted
// dump without it.
std::string Reseal(std::string_view text) {
  nlohmann::json state = nlohmann::json::parse(text, nullptr, false);
  if (state.is_discarded() || !state.is_object()) return std::string(text);
  state.erase("checksum");
  const std::string dump = state.dump();
  state["checksum"] =
      static_cast<uint32_t>(crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(dump.data()),
                                  static_cast<uInt>(dump.size())));
  return state.dump();
}

void WriteSeeds(const fs::path& dir) {
  const Run& run = TheRun();
  const std::string sealed = run.SealedStep2();
  Write(dir / "sealed_state", std::string(1, '\0') + sealed);
  // resealed by the harness: an edited step, and a file list that names others
  nlohmann::json edited = nlohmann::json::parse(sealed);
  edited["step"] = 3;
  Write(dir / "edited_step", std::string(1, '\1') + edited.dump());
  edited["files"]["other.bin"] = {{"bytes", 3}, {"crc32", 7}};
  Write(dir / "extra_file", std::string(1, '\1') + edited.dump());
  // written before the checks existed: no files, run_files or checksum
  Write(dir / "unchecked_state", std::string(1, '\0') + TrainerState(2).dump());
  std::exit(0);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MANYWORLDS_FUZZ_WRITE_SEEDS")) WriteSeeds(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const Run& run = TheRun();
  if (size == 0) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  Write(run.step2 / "state.json", (data[0] & 1) ? Reseal(text) : std::string(text));

  std::optional<std::string> problem;
  try {
    problem = ex::CheckpointProblem(run.step2);
  } catch (...) {
    std::fprintf(stderr, "CheckpointProblem threw\n");
    std::abort();
  }
  bool run_files_match = true;
  try {
    ex::CheckRunFiles(run.step2, run.root);
  } catch (const manyworlds::Error&) {
    run_files_match = false;
  }
  try {
    ex::VerifyCheckpoint(run.step2, run.root);
    if (problem || !run_files_match) std::abort();
  } catch (const manyworlds::Error&) {
    if (!problem && run_files_match) std::abort();
  }
  try {
    const ex::ChosenCheckpoint chosen = ex::ChooseCheckpoint(run.root);
    if (!problem) {
      if (chosen.dir != run.step2 || !chosen.warnings.empty()) std::abort();
    } else if (chosen.dir != run.step1 || chosen.warnings.size() != 1) {
      std::abort();
    }
  } catch (const manyworlds::Error&) {
    // only the run files of an intact step 2 may stop the choice
    if (problem || run_files_match) std::abort();
  }
  return 0;
}
