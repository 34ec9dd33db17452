#include "manyworlds/experiments/run/checkpoint_integrity.h"

#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstdint>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

constexpr const char* kStateFile = "state.json";
constexpr const char* kRunFiles[] = {"config.yaml", "tasks.json", "eval_tasks.json"};
constexpr int kMaxStateDepth = 64;

struct FileSum {
  int64_t bytes = 0;
  uint32_t crc = 0;
};

// Only regular files are read: a device or a pipe (/dev/zero, a FIFO) would
// never end.
std::optional<FileSum> Sum(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return std::nullopt;
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
  std::error_code ec;
  if (!fs::is_regular_file(dir / kStateFile, ec)) {  // opening a pipe would block
    *problem = "state.json is missing or not a regular file";
    return std::nullopt;
  }
  std::ifstream in(dir / kStateFile, std::ios::binary);
  if (!in) {
    *problem = "state.json is missing";
    return std::nullopt;
  }
  std::stringstream text;
  text << in.rdbuf();
  // nlohmann's parser is iterative, but copying and dumping a tree recurse
  // once per level: a state.json of 200,000 '[' overflowed the stack in
  // StateCrc. A trainer's state nests 4 levels; deeper values are dropped
  // while parsing and the file is refused.
  bool too_deep = false;
  const nlohmann::json::parser_callback_t limit_depth =
      [&too_deep](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
        if (depth > kMaxStateDepth && (event == nlohmann::json::parse_event_t::object_start ||
                                       event == nlohmann::json::parse_event_t::array_start)) {
          too_deep = true;
          return false;
        }
        return true;
      };
  nlohmann::json state = nlohmann::json::parse(text.str(), limit_depth, false);
  if (state.is_discarded() || !state.is_object()) {
    *problem = "state.json is not valid JSON";
    return std::nullopt;
  }
  if (too_deep) {
    *problem = "state.json nests deeper than " + std::to_string(kMaxStateDepth) + " levels";
    return std::nullopt;
  }
  return state;
}

// A file name inside one directory: no path, so that a state.json can make
// nothing outside its checkpoint (or run) directory be read.
bool IsPlainName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." &&
         name.find_first_of(std::string("/\0", 2)) == std::string::npos;
}

// A JSON integer in [0, max], or nothing (a float, a string, a negative or a
// larger number: converting those was undefined behaviour or threw).
std::optional<uint64_t> Count(const nlohmann::json& value, uint64_t max) {
  if (value.is_number_unsigned()) {
    const auto n = value.get<uint64_t>();
    if (n <= max) return n;
  } else if (value.is_number_integer()) {
    const auto n = value.get<int64_t>();
    if (n >= 0 && static_cast<uint64_t>(n) <= max) return static_cast<uint64_t>(n);
  }
  return std::nullopt;
}

// A name from state.json for a message: JSON-quoted (no control characters
// reach the terminal) and shortened.
std::string Quoted(const std::string& name) {
  const std::string quoted = nlohmann::json(name).dump();
  return quoted.size() <= 80 ? quoted : quoted.substr(0, 76) + "...\"";
}

constexpr uint64_t kMaxCrc = 0xffffffffULL;
constexpr uint64_t kMaxBytes = static_cast<uint64_t>(std::numeric_limits<int64_t>::max());

// What is wrong with the "files" and "run_files" records of a state whose
// checksum matched (so a program, or a person, wrote them): names that are
// not plain file names, values that are not sizes or CRC-32s.
std::optional<std::string> RecordProblem(const nlohmann::json& state) {
  const nlohmann::json files = state.value("files", nlohmann::json::object());
  if (!files.is_object()) return "state.json: 'files' is not an object";
  for (const auto& [name, want] : files.items()) {
    if (!IsPlainName(name))
      return "state.json: 'files' names " + Quoted(name) + ", not a file name";
    if (!want.is_object() || !want.contains("bytes") || !want.contains("crc32") ||
        !Count(want["bytes"], kMaxBytes) || !Count(want["crc32"], kMaxCrc)) {
      return "state.json: 'files' entry " + Quoted(name) + " is not {\"bytes\": N, \"crc32\": N}";
    }
  }
  const nlohmann::json run_files = state.value("run_files", nlohmann::json::object());
  if (!run_files.is_object()) return "state.json: 'run_files' is not an object";
  for (const auto& [name, crc] : run_files.items()) {
    if (!IsPlainName(name)) {
      return "state.json: 'run_files' names " + Quoted(name) + ", not a file name";
    }
    if (!Count(crc, kMaxCrc))
      return "state.json: 'run_files' entry " + Quoted(name) + " is not a CRC-32";
  }
  return std::nullopt;
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
  if (!state->contains("checksum")) {
    // Written before the checks existed, and accepted unchecked; unless it
    // records files, which a sealed state does: then the damage hit the
    // word "checksum" itself (one flipped bit turned every check off).
    if (state->contains("files") || state->contains("run_files")) {
      return "state.json was damaged (it records file checksums but has no checksum of its own)";
    }
    return std::nullopt;
  }
  const nlohmann::json& recorded = (*state)["checksum"];
  if (!recorded.is_number_unsigned() || recorded.get<uint64_t>() != StateCrc(*state)) {
    return "state.json was edited or damaged (its checksum does not match its content)";
  }
  if (auto record_problem = RecordProblem(*state)) return record_problem;
  const nlohmann::json files = state->value("files", nlohmann::json::object());
  for (const auto& [name, want] : files.items()) {
    const std::optional<FileSum> sum = Sum(dir / name);
    if (!sum) return name + " is missing or unreadable";
    const uint64_t bytes = *Count(want["bytes"], kMaxBytes);
    if (static_cast<uint64_t>(sum->bytes) != bytes) {
      return name + " has " + std::to_string(sum->bytes) + " bytes, expected " +
             std::to_string(bytes);
    }
    if (sum->crc != *Count(want["crc32"], kMaxCrc)) return name + " is damaged (CRC-32 mismatch)";
  }
  return std::nullopt;
}

void CheckRunFiles(const fs::path& checkpoint_dir, const fs::path& run_dir) {
  std::string problem;
  const std::optional<nlohmann::json> state = ReadState(checkpoint_dir, &problem);
  if (!state || !state->contains("run_files") || !(*state)["run_files"].is_object()) return;
  for (const auto& [name, crc] : (*state)["run_files"].items()) {
    if (!IsPlainName(name)) {
      throw Error("checkpoint '" + checkpoint_dir.string() + "': state.json names run file " +
                  Quoted(name) + ", which is not a file name");
    }
    const std::optional<FileSum> sum = Sum(run_dir / name);
    if (!sum || !crc.is_number_unsigned() || sum->crc != crc.get<uint64_t>()) {
      throw Error("'" + (run_dir / name).string() + "' is " + (sum ? "not" : "missing, not") +
                  " the file this run was trained with (checkpoint " + Step(checkpoint_dir) +
                  " recorded another checksum): it was edited or damaged; restore it, or start "
                  "a new run with `manyworlds train`");
    }
  }
}

std::string CheckpointName(int64_t step) {
  char name[32];
  std::snprintf(name, sizeof(name), "%s%012lld", kCheckpointPrefix, static_cast<long long>(step));
  return name;
}

std::vector<fs::path> ListCheckpoints(const fs::path& run_dir) {
  const fs::path dir = run_dir / kCheckpointsDir;
  std::vector<fs::path> found;
  if (!fs::is_directory(dir)) return found;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && name.rfind(kCheckpointPrefix, 0) == 0) {
      found.push_back(entry.path());
    }
  }
  // zero-padded steps: the names sort by step
  std::sort(found.begin(), found.end());
  return found;
}

namespace {

// The newest intact checkpoint among `listed` (ListCheckpoints' order: oldest first).
ChosenCheckpoint ChooseAmong(const std::vector<fs::path>& listed, const fs::path& run_dir) {
  ChosenCheckpoint chosen;
  for (auto it = listed.rbegin(); it != listed.rend(); ++it) {
    const fs::path& candidate = *it;
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

}  // namespace

ChosenCheckpoint ChooseCheckpoint(const fs::path& run_dir) {
  const fs::path dir = run_dir / kCheckpointsDir;
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw ConfigError("'" + dir.string() + "' is not a directory, so run '" + run_dir.string() +
                      "' has no checkpoint");
  }
  // A run that is training writes a checkpoint and then prunes the older ones: those listed may
  // vanish while they are checked. Then the list has changed, and the choice is made again.
  constexpr int kAttempts = 10;
  for (int attempt = 1;; ++attempt) {
    const std::vector<fs::path> listed = ListCheckpoints(run_dir);
    if (listed.empty()) throw ConfigError("run '" + run_dir.string() + "' has no checkpoint yet");
    try {
      return ChooseAmong(listed, run_dir);
    } catch (const std::exception&) {
      if (attempt == kAttempts || ListCheckpoints(run_dir) == listed) throw;
    }
  }
}

void VerifyCheckpoint(const fs::path& checkpoint_dir, const fs::path& run_dir) {
  if (const auto problem = CheckpointProblem(checkpoint_dir)) {
    throw Error("checkpoint '" + checkpoint_dir.string() + "' is damaged: " + *problem);
  }
  CheckRunFiles(checkpoint_dir, run_dir);
}

}  // namespace manyworlds::experiments
