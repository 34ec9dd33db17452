// The run-directory probe: the commands that read a run (`eval`, `train --resume`, `rollout
// --policy checkpoint:`, `eval --protocol meta-test`) on a table of damaged, foreign and hostile
// run directories, through the built program (MANYWORLDS_CLI_PATH) under a time limit. Each
// case must end with exit code 1 or 2 and one error line (or 0 where the damage leaves an
// intact checkpoint to use), never a signal or a hang, and must leave the directory as it was
// (nothing lost).
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/cli_runner.h"
#include "tests/support/scratch_dir.h"

namespace manyworlds {
namespace {

namespace fs = std::filesystem;

using test_support::IsOneErrorLine;
using test_support::RunResult;
using test_support::Slurp;

constexpr int kCaseSeconds = 30;

constexpr char kTinyConfig[] = R"(env:
  id: point-nav
  options: {horizon: 20}
agent:
  hidden_dim: 8
  num_layers: 1
  batch_size: 16
replay:
  capacity: 1000
experiment:
  steps_per_task: 160
  warmup_steps: 20
  eval_every: 0
  eval_episodes: 1
  checkpoint_every: 40
  keep_checkpoints: 0
  run_dir: pristine
)";

// Every file under `dir` with its bytes (a FIFO or device by its kind only), to show that a
// command changed nothing.
std::map<std::string, std::string> Snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return files;
  for (auto it = fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied, ec);
       it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) break;
    const fs::path& path = it->path();
    if (path.filename() == ".lock") continue;  // the run lock's file is created by readers too
    const std::string key = path.lexically_relative(dir).string();
    if (fs::is_symlink(it->symlink_status())) {
      files[key] = "symlink";
    } else if (fs::is_regular_file(it->symlink_status())) {
      files[key] = Slurp(path);
    } else {
      files[key] = fs::is_directory(it->symlink_status()) ? "dir" : "special";
    }
  }
  return files;
}

TEST(RunDirProbeTest, CommandsOnDamagedForeignAndHostileRunsFailInOneLineAndLoseNothing) {
  const fs::path root = test_support::ScratchDir("run_dir_probe", "runs", /*create=*/true);
  std::ofstream(root / "tiny.yaml") << kTinyConfig;
  // stopped at step 80 of 160, checkpoints at 40 and 80: a run that resume would continue
  const RunResult trained =
      test_support::RunProgram(MANYWORLDS_CLI_PATH, "train tiny.yaml --stop-after 80", root);
  ASSERT_EQ(trained.exit_code, 0) << trained.err;
  ASSERT_TRUE(fs::exists(root / "pristine/checkpoints/step_000000000080/state.json"));
  ASSERT_FALSE(fs::exists(root / "pristine/summary.json"));
  const fs::path pristine = root / "pristine";
  const fs::path newest = fs::path("checkpoints") / "step_000000000080";

  // name -> how to damage a copy of the pristine run (or make something that is not one)
  const std::vector<std::pair<std::string, std::function<void(const fs::path&)>>> inputs = {
      {"missing", [](const fs::path& d) { fs::remove_all(d); }},
      {"a file", [](const fs::path& d) { fs::remove_all(d); std::ofstream(d) << "x"; }},
      {"an empty directory", [](const fs::path& d) { fs::remove_all(d); fs::create_directory(d); }},
      {"a foreign directory",
       [](const fs::path& d) {
         fs::remove_all(d);
         fs::create_directories(d / "checkpoints" / "step_12");
         std::ofstream(d / "config.yaml") << "hello: [world";
         std::ofstream(d / "checkpoints" / "step_12" / "state.json") << "{";
       }},
      {"config.yaml a FIFO",
       [](const fs::path& d) {
         fs::remove(d / "config.yaml");
         mkfifo((d / "config.yaml").c_str(), 0644);
       }},
      {"newest learner.pt a FIFO",
       [&](const fs::path& d) {
         fs::remove(d / newest / "learner.pt");
         mkfifo((d / newest / "learner.pt").c_str(), 0644);
       }},
      {"every learner.pt truncated",
       [](const fs::path& d) {
         for (const auto& e : fs::recursive_directory_iterator(d)) {
           if (e.path().filename() == "learner.pt") fs::resize_file(e.path(), 10);
         }
       }},
      {"newest state.json a JSON bomb",
       [&](const fs::path& d) {
         std::ofstream(d / newest / "state.json", std::ios::trunc)
             << std::string(200000, '[') << std::string(200000, ']');
       }},
      {"checkpoints/ a file",
       [](const fs::path& d) {
         fs::remove_all(d / "checkpoints");
         std::ofstream(d / "checkpoints") << "x";
       }},
      {"checkpoints/ a symlink loop",
       [](const fs::path& d) {
         fs::remove_all(d / "checkpoints");
         fs::create_directory_symlink("checkpoints", d / "checkpoints");
       }},
      {"tasks.json edited",
       [](const fs::path& d) { std::ofstream(d / "tasks.json", std::ios::app) << " "; }},
      {"tasks.json binary junk",
       [](const fs::path& d) {
         std::ofstream(d / "tasks.json", std::ios::trunc | std::ios::binary)
             << std::string("\x00\xff\xfe{[", 5);
       }},
      {"read-only", [](const fs::path& d) {
         for (const auto& e : fs::recursive_directory_iterator(d)) {
           fs::permissions(e.path(), fs::perms::owner_write | fs::perms::group_write |
                                         fs::perms::others_write,
                           fs::perm_options::remove);
         }
         fs::permissions(d, fs::perms::owner_write, fs::perm_options::remove);
       }},
  };
  const std::vector<std::string> commands = {
      "eval RUN --episodes 1", "train --resume RUN", "rollout --policy checkpoint:RUN --episodes 1",
      "eval RUN --checkpoint step_000000000080 --json"};
  // cases whose damage leaves an intact checkpoint (or only a read-only directory): a command
  // may succeed there
  const std::map<std::string, bool> may_succeed = {{"newest learner.pt a FIFO", true},
                                                   {"newest state.json a JSON bomb", true},
                                                   {"read-only", true}};
  int cases = 0;
  for (size_t i = 0; i < inputs.size(); ++i) {
    for (size_t c = 0; c < commands.size(); ++c) {
      const fs::path run = root / ("case_" + std::to_string(i) + "_" + std::to_string(c));
      fs::copy(pristine, run, fs::copy_options::recursive);
      inputs[i].second(run);
      const auto before = Snapshot(run);
      std::string command = commands[c];
      command.replace(command.find("RUN"), 3, run.filename().string());
      const RunResult r = test_support::RunProgram(
          "timeout", "-s KILL " + std::to_string(kCaseSeconds) + " '" + MANYWORLDS_CLI_PATH +
                         "' " + command,
          root);
      ++cases;
      const std::string label = inputs[i].first + ": manyworlds " + command;
      EXPECT_NE(r.exit_code, -1) << label << ": killed by a signal";
      EXPECT_NE(r.exit_code, 137) << label << ": still running after " << kCaseSeconds << " s";
      const bool succeeded = r.exit_code == 0;
      if (succeeded) {
        EXPECT_TRUE(may_succeed.count(inputs[i].first)) << label << ": exit 0\n" << r.err;
      } else {
        EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << label << ": exit " << r.exit_code
                                                         << "\n" << r.err;
        EXPECT_TRUE(IsOneErrorLine(r.err)) << label << "\n" << r.err.substr(0, 2000);
      }
      // nothing lost: a failed command leaves the directory as it was (train --resume that
      // succeeds may add to it)
      if (!succeeded) EXPECT_TRUE(Snapshot(run) == before) << label << ": the directory changed";
      std::error_code ec;
      fs::permissions(run, fs::perms::owner_all, fs::perm_options::add, ec);
      for (auto it = fs::recursive_directory_iterator(run, ec); !ec && it != fs::recursive_directory_iterator();
           it.increment(ec)) {
        if (!fs::is_symlink(it->symlink_status())) {
          fs::permissions(it->path(), fs::perms::owner_all, fs::perm_options::add, ec);
        }
      }
      fs::remove_all(run, ec);
    }
  }
  std::printf("run-directory probe: %d cases (%zu inputs x %zu commands)\n", cases, inputs.size(),
              commands.size());
  RecordProperty("cases", cases);
  fs::remove_all(root);
}

}  // namespace
}  // namespace manyworlds
