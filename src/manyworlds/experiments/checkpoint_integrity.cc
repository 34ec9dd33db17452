#include "manyworlds/experiments/checkpoint_integrity.h"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

constexpr const char* kStateFile = "state.json";
constexpr const char* kRunFiles[] = {"config.yaml", "tasks.json", "eval_tasks.json"};

struct FileSum {
  int64_t bytes = 0;
  uint32_t crc = 0;
};

std::optional<FileSum> Sum(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  FileSum sum;
  uLong crc = crc32(0L, Z_NULL, 0);
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const std::streamsize n = in.gcount();
    if (n <= 0) break;
    crc = crc32(crc, reinterpret_cast<const Bytef*>(buffer.data()), static_cast<uInt>(n));
    sum.bytes += n;
  }
  if (in.bad()) return std::nullopt;
  sum.crc = static_cast<uint32_t>(crc);
  return sum;
}

uint32_t TextCrc(const std::string& text) {
  return static_cast<uint32_t>(crc32(crc32(0L, Z_NULL, 0),
                                     reinterpret_cast<const Bytef*>(text.data()),
                                     static_cast<uInt>(text.size())));
}

// The CRC of state.json's content without its "checksum" field (nlohmann
// objects are key-sorted, so the dump is canonical).
uint32_t StateCrc(nlohmann::json state) {
  state.erase("checksum");
  return TextCrc(state.dump());
}

std::optional<nlohmann::json> ReadState(const fs::path& dir, std::string* problem) {
  std::ifstream in(dir / kStateFile, std::ios::binary);
  if (!in) {
    *problem = "state.json is missing";
    return std::nullopt;
  }
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json state = nlohmann::json::parse(text.str(), nullptr, false);
  if (state.is_discarded() || !state.is_object()) {
    *problem = "state.json is not valid JSON";
    return std::nullopt;
  }
  return state;
}

std::string Step(const fs::path& dir) { return dir.filename().string(); }

}  // namespace

void SealCheckpointState(const fs::path& checkpoint_dir, const fs::path& run_dir,
                         nlohmann::json& state) {
  nlohmann::json files = nlohmann::json::object();
  for (const auto& entry : fs::directory_iterator(checkpoint_dir)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || name == kStateFile) continue;
    const std::optional<FileSum> sum = Sum(entry.path());
    if (!sum) throw Error("cannot read back '" + entry.path().string() + "'");
    files[name] = {{"bytes", sum->bytes}, {"crc32", sum->crc}};
  }
  nlohmann::json run_files = nlohmann::json::object();
  for (const char* name : kRunFiles) {
    if (!fs::exists(run_dir / name)) continue;
    const std::optional<FileSum> sum = Sum(run_dir / name);
    if (!sum) throw Error("cannot read '" + (run_dir / name).string() + "'");
    run_files[name] = sum->crc;
  }
  state["files"] = files;
  state["run_files"] = run_files;
  state["checksum"] = StateCrc(state);
}

std::optional<std::string> CheckpointProblem(const fs::path& dir) {
  std::string problem;
  const std::optional<nlohmann::json> state = ReadState(dir, &problem);
  if (!state) return problem;
  if (!state->contains("checksum")) return std::nullopt;  // written before the checks
  const nlohmann::json& recorded = (*state)["checksum"];
  if (!recorded.is_number_unsigned() || recorded.get<uint64_t>() != StateCrc(*state)) {
    return "state.json was edited or damaged (its checksum does not match its content)";
  }
  const nlohmann::json files = state->value("files", nlohmann::json::object());
  if (!files.is_object()) return "state.json: 'files' is not an object";
  for (const auto& [name, want] : files.items()) {
    const std::optional<FileSum> sum = Sum(dir / name);
    if (!sum) return name + " is missing or unreadable";
    const int64_t bytes = want.value("bytes", int64_t{-1});
    if (sum->bytes != bytes) {
      return name + " has " + std::to_string(sum->bytes) + " bytes, expected " +
             std::to_string(bytes);
    }
    if (sum->crc != want.value("crc32", uint32_t{0})) return name + " is damaged (CRC-32 mismatch)";
  }
  return std::nullopt;
}

void CheckRunFiles(const fs::path& checkpoint_dir, const fs::path& run_dir) {
  std::string problem;
  const std::optional<nlohmann::json> state = ReadState(checkpoint_dir, &problem);
  if (!state || !state->contains("run_files") || !(*state)["run_files"].is_object()) return;
  for (const auto& [name, crc] : (*state)["run_files"].items()) {
    const std::optional<FileSum> sum = Sum(run_dir / name);
    if (!sum || !crc.is_number_unsigned() || sum->crc != crc.get<uint64_t>()) {
      throw Error("'" + (run_dir / name).string() + "' is " + (sum ? "not" : "missing, not") +
                  " the file this run was trained with (checkpoint " + Step(checkpoint_dir) +
                  " recorded another checksum): it was edited or damaged; restore it, or start "
                  "a new run with `manyworlds train`");
    }
  }
}

ChosenCheckpoint ChooseCheckpoint(const fs::path& run_dir) {
  const fs::path dir = run_dir / "checkpoints";
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw ConfigError("'" + dir.string() + "' is not a directory, so run '" + run_dir.string() +
                      "' has no checkpoint");
  }
  std::vector<fs::path> found;
  if (fs::is_directory(dir)) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (entry.is_directory() && name.rfind("step_", 0) == 0) found.push_back(entry.path());
    }
  }
  if (found.empty()) throw ConfigError("run '" + run_dir.string() + "' has no checkpoint yet");
  std::sort(found.rbegin(), found.rend());
  ChosenCheckpoint chosen;
  for (const fs::path& candidate : found) {
    if (const auto problem = CheckpointProblem(candidate)) {
      chosen.warnings.push_back("checkpoint '" + candidate.string() + "' is damaged (" + *problem +
                                "); skipped");
      continue;
    }
    CheckRunFiles(candidate, run_dir);
    chosen.dir = candidate;
    return chosen;
  }
  std::string all;
  for (const std::string& w : chosen.warnings) all += (all.empty() ? "" : "; ") + w;
  throw Error("run '" + run_dir.string() + "' has no intact checkpoint: " + all);
}

void VerifyCheckpoint(const fs::path& checkpoint_dir, const fs::path& run_dir) {
  if (const auto problem = CheckpointProblem(checkpoint_dir)) {
    throw Error("checkpoint '" + checkpoint_dir.string() + "' is damaged: " + *problem);
  }
  CheckRunFiles(checkpoint_dir, run_dir);
}

}  // namespace manyworlds::experiments
