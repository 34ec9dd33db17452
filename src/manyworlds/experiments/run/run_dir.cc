#include "manyworlds/experiments/run/run_dir.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "manyworlds/config/yaml.h"
#include "manyworlds/core/atomic_file.h"
#include "manyworlds/core/error.h"
#include "manyworlds/experiments/run/checkpoint_integrity.h"
#include "manyworlds/nn/threads.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

constexpr char kLatestFile[] = "latest";

// a run's files: never a FIFO (config.yaml as a pipe hung eval, rollout and resume)
std::string ReadText(const fs::path& path) { return ReadRegularFile(path); }

// A task set file of a run; Error naming the file if it is not one.
TaskSet ReadTaskSet(const fs::path& path) {
  const auto json = nlohmann::json::parse(ReadText(path), nullptr, false);
  if (json.is_discarded()) throw Error(path.string() + ": not valid JSON");
  try {
    return TaskSet::FromJson(json);
  } catch (const Error& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

}  // namespace

RunInfo RunInfo::Read(const fs::path& run_dir) {
  const RunPaths paths{run_dir};
  std::error_code ec;
  if (!fs::is_directory(run_dir, ec)) {
    const bool exists = fs::exists(fs::symlink_status(run_dir, ec));
    throw ConfigError("run directory '" + run_dir.string() + "' " +
                      (exists ? "is not a directory (a run directory holds config.yaml, "
                                "tasks.json and checkpoints/)"
                              : "does not exist"));
  }
  if (!fs::exists(paths.config()) || !fs::exists(paths.tasks())) {
    throw ConfigError("'" + run_dir.string() +
                      "' is not a run directory (no config.yaml and tasks.json)");
  }
  RunInfo info;
  info.config = TrainConfig::Load(paths.config());
  info.config.Validate();
  info.tasks = ReadTaskSet(paths.tasks());
  if (info.config.eval_env) info.eval_tasks = ReadTaskSet(paths.eval_tasks());
  return info;
}

std::optional<int64_t> FinishedRunStep(const fs::path& run_dir) {
  const fs::path path = RunPaths{run_dir}.summary();
  std::error_code ec;
  if (!fs::is_regular_file(path, ec) || fs::file_size(path, ec) > (int64_t{64} << 20) || ec) {
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // summary.json is flat but for a few levels; a deeper one is not ours
  const auto depth_limit = [](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
    return depth <= 16;
  };
  const nlohmann::json summary = nlohmann::json::parse(text, depth_limit, /*allow_exceptions=*/false);
  if (!summary.is_object() || summary.value("finished", nlohmann::json()) != true) {
    return std::nullopt;
  }
  const auto step = summary.find("step");
  if (step == summary.end() || !step->is_number_integer()) return std::nullopt;
  return step->get<int64_t>();
}

void RefuseExistingRun(const fs::path& run_dir) {
  const RunPaths paths{run_dir};
  // an empty checkpoints/ without config.yaml is a creation cut short
  std::error_code ec;
  const bool empty_checkpoints =
      fs::is_directory(paths.checkpoints(), ec) && fs::is_empty(paths.checkpoints(), ec) && !ec;
  if (fs::exists(paths.config()) ||
      (fs::exists(fs::symlink_status(paths.checkpoints())) && !empty_checkpoints)) {
    throw ConfigError("run directory '" + run_dir.string() +
                      "' already holds a run; continue it with `manyworlds train --resume " +
                      run_dir.string() + "` or choose another experiment.run_dir");
  }
}

std::unique_ptr<RunLock> CreateRunDirectory(const fs::path& run_dir, const TrainConfig& config,
                                            const TaskSet& tasks,
                                            const std::optional<TaskSet>& eval_tasks) {
  const RunPaths paths{run_dir};
  std::error_code ec;
  fs::create_directories(run_dir, ec);
  if (ec) {
    throw Error("cannot create run directory '" + run_dir.string() + "': " + ec.message());
  }
  auto lock = std::make_unique<RunLock>(run_dir);
  RefuseExistingRun(run_dir);
  if (eval_tasks) AtomicWriteFile(paths.eval_tasks(), eval_tasks->ToJson().dump(2) + "\n");
  AtomicWriteFile(paths.tasks(), tasks.ToJson().dump(2) + "\n");
  fs::create_directories(paths.checkpoints(), ec);
  if (ec) {
    throw Error("cannot create '" + paths.checkpoints().string() + "': " + ec.message());
  }
  FsyncPath(run_dir, /*directory=*/true);
  AtomicWriteFile(paths.config(), DumpYaml(config.ToJson()));
  return lock;
}

void RemoveStaleTemporaries(const fs::path& run_dir) {
  for (const fs::path& dir : {run_dir, RunPaths{run_dir}.checkpoints()}) {
    std::error_code ec;
    if (!fs::is_directory(fs::symlink_status(dir, ec))) continue;
    std::vector<fs::path> stale;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      const bool temp_file = name.size() > 1 && name[0] == '.' &&
                             name.find(".tmp.") != std::string::npos && entry.is_regular_file(ec);
      const bool temp_checkpoint = name.rfind(std::string(".tmp_") + kCheckpointPrefix, 0) == 0;
      if (temp_file || temp_checkpoint) stale.push_back(entry.path());
    }
    for (const fs::path& p : stale) fs::remove_all(p, ec);
  }
}

fs::path WriteCheckpoint(const fs::path& run_dir, int64_t step, int64_t keep, nlohmann::json state,
                         const std::function<void(const fs::path&, nlohmann::json&)>& write_files) {
  const fs::path dir = RunPaths{run_dir}.checkpoints();
  fs::create_directories(dir);
  const std::string name = CheckpointName(step);
  const fs::path final_dir = dir / name;
  const fs::path tmp = dir / (".tmp_" + name);
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  // a failed write (full disk, I/O error) removes the partial checkpoint and
  // leaves the previous one as the newest: the run resumes from there
  struct RemoveUnlessDone {
    const fs::path& dir;
    bool done = false;
    ~RemoveUnlessDone() {
      std::error_code ignored;
      if (!done) fs::remove_all(dir, ignored);
    }
  } cleanup{tmp};
  write_files(tmp, state);
  SealCheckpointState(tmp, run_dir, state);
  AtomicWriteFile(tmp / "state.json", state.dump(2) + "\n");
  for (const auto& entry : fs::directory_iterator(tmp)) FsyncPath(entry.path(), false);
  FsyncPath(tmp, true);
  fs::remove_all(final_dir);
  fs::rename(tmp, final_dir);
  cleanup.done = true;
  FsyncPath(dir, true);
  AtomicWriteFile(dir / kLatestFile, name + "\n");

  // prune older checkpoints beyond keep (never the newest)
  if (keep > 0) {
    const std::vector<fs::path> found = ListCheckpoints(run_dir);
    for (size_t i = 0; i + keep < found.size(); ++i) {
      if (found[i] != final_dir) fs::remove_all(found[i]);
    }
  }
  return final_dir;
}

nlohmann::json ReadCheckpointState(const fs::path& checkpoint) {
  try {
    return nlohmann::json::parse(ReadText(checkpoint / "state.json"));
  } catch (const std::exception& e) {
    const std::string what = e.what();
    throw Error("checkpoint '" + checkpoint.string() +
                "': unreadable state.json: " + what.substr(0, what.find('\n')));
  }
}

int64_t CheckpointStep(const fs::path& checkpoint) {
  const auto state = nlohmann::json::parse(ReadText(checkpoint / "state.json"), nullptr, false);
  if (state.is_object() && state.contains("step") && state["step"].is_number_integer() &&
      state["step"].get<int64_t>() >= 0) {
    return state["step"].get<int64_t>();
  }
  throw Error("checkpoint '" + checkpoint.string() + "': state.json has no valid step");
}

fs::path LatestCheckpoint(const fs::path& run_dir) { return ChooseCheckpoint(run_dir).dir; }

nlohmann::json ThreadRecord() {
  const nn::ThreadInfo threads = nn::CurrentThreads();
  return {{"torch_intra_op", threads.torch_intra_op},
          {"blas_threads", threads.blas_threads},
          {"blas_core", threads.blas_core},
          {"gemm", threads.gemm}};
}

std::optional<std::string> ThreadCountMismatch(const fs::path& checkpoint,
                                               const nlohmann::json& record) {
  const nn::ThreadInfo now = nn::CurrentThreads();
  const int64_t torch_then = record.value("torch_intra_op", int64_t{-1});
  const int64_t blas_then = record.value("blas_threads", int64_t{-1});
  if (torch_then == now.torch_intra_op && blas_then == now.blas_threads) return std::nullopt;
  return "checkpoint '" + checkpoint.string() + "' was written with " + std::to_string(blas_then) +
         " BLAS thread(s) and " + std::to_string(torch_then) +
         " torch thread(s); this process has " + std::to_string(now.blas_threads) + " and " +
         std::to_string(now.torch_intra_op);
}

std::optional<std::string> EvaluationThreadWarning(const fs::path& checkpoint) {
  try {
    const nlohmann::json state = nlohmann::json::parse(ReadText(checkpoint / "state.json"));
    if (!state.is_object() || !state.contains("threads") || !state["threads"].is_object()) {
      return std::nullopt;  // older checkpoints
    }
    const nlohmann::json& saved = state["threads"];
    const auto mismatch = ThreadCountMismatch(checkpoint, saved);
    if (!mismatch) return std::nullopt;
    return *mismatch +
           ": the numbers may differ from the run's own evaluations in the "
           "rounding, and sampled episodes then diverge; OPENBLAS_NUM_THREADS=" +
           std::to_string(saved.value("blas_threads", int64_t{-1})) + " reproduces them";
  } catch (const std::exception&) {
    return std::nullopt;  // a damaged checkpoint is the evaluation's error to report
  }
}

void FsyncPath(const fs::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0)
    throw Error("cannot open '" + path.string() + "' to sync it: " + std::strerror(errno));
  const int synced = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  // directories on some file systems refuse fsync (EINVAL): nothing to report there
  if (synced != 0 && !(directory && error == EINVAL)) {
    throw Error("cannot sync '" + path.string() + "': " + std::strerror(error));
  }
}

}  // namespace manyworlds::experiments
