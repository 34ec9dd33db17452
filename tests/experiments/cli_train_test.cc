// Runs the built `manyworlds` program (MANYWORLDS_CLI_PATH): train with a
// tiny config writes every run-directory file, eval reads it back, resume
// continues, and bad input gives one error line and the documented exit code.
#include <gtest/gtest.h>
#include <dlfcn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "manyworlds/experiments/algorithms.h"
#include "tests/support/cli_runner.h"
#include "tests/support/scratch_dir.h"

namespace manyworlds {
namespace {

namespace fs = std::filesystem;

using test_support::IsOneErrorLine;
using test_support::RunResult;
using test_support::Slurp;

// Runs `manyworlds <args>` in `cwd`.
RunResult RunCli(const std::string& args, const fs::path& cwd) {
  return test_support::RunProgram(MANYWORLDS_CLI_PATH, args, cwd);
}

fs::path ScratchDir() {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  return test_support::ScratchDir("cli_train", info->name(), /*create=*/true);
}

constexpr char kTinyConfig[] = R"(env:
  id: point-nav
  options: {horizon: 50}
agent:
  hidden_dim: 16
  num_layers: 2
  batch_size: 32
replay:
  capacity: 5000
experiment:
  steps_per_task: 300
  warmup_steps: 100
  eval_every: 100
  eval_episodes: 2
  checkpoint_every: 150
  keep_checkpoints: 0
  run_dir: runs/tiny
)";

TEST(CliTrainTest, TrainWritesTheRunDirectoryAndEvalReadsIt) {
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "tiny.yaml") << kTinyConfig;
  const RunResult train = RunCli("train tiny.yaml experiment.seed=3", dir);
  ASSERT_EQ(train.exit_code, 0) << train.err;
  EXPECT_NE(train.out.find("point-nav"), std::string::npos) << train.out;
  EXPECT_NE(train.out.find("success"), std::string::npos) << train.out;
  const fs::path run = dir / "runs/tiny";
  for (const char* file : {"config.yaml", "tasks.json", "metrics.jsonl", "metrics.csv",
                           "eval.jsonl", "eval.csv", "summary.json", "checkpoints/latest",
                           "checkpoints/step_000000000150/learner.pt",
                           "checkpoints/step_000000000300/learner.pt",
                           "checkpoints/step_000000000300/replay.bin",
                           "checkpoints/step_000000000300/state.json"}) {
    EXPECT_TRUE(fs::exists(run / file)) << file;
  }
  EXPECT_NE(Slurp(run / "config.yaml").find("seed: 3"), std::string::npos);
  EXPECT_EQ(Slurp(run / "checkpoints/latest"), "step_000000000300\n");
  const auto summary = nlohmann::json::parse(Slurp(run / "summary.json"));
  EXPECT_TRUE(summary["finished"].get<bool>());
  EXPECT_EQ(summary["step"], 300);
  EXPECT_GT(summary["env_steps_per_s"].get<double>(), 0);
  EXPECT_TRUE(summary["final_eval"]["mean_success"].is_number());
  // metrics: one row per 50-step round; CSV header names the columns
  const std::string csv = Slurp(run / "metrics.csv");
  EXPECT_EQ(csv.rfind("step,", 0), 0u) << csv.substr(0, 200);
  EXPECT_NE(csv.find("critic_loss"), std::string::npos);
  EXPECT_NE(csv.find("env_steps_per_s"), std::string::npos);
  EXPECT_NE(Slurp(run / "eval.csv").find("per_task.point-nav.success"), std::string::npos);

  const RunResult eval = RunCli("eval runs/tiny --json", dir);
  ASSERT_EQ(eval.exit_code, 0) << eval.err;
  const auto json = nlohmann::json::parse(eval.out);
  ASSERT_TRUE(json.contains("per_task"));
  ASSERT_TRUE(json["per_task"].contains("point-nav"));
  // same checkpoint, same episodes: the number logged at the end of training
  EXPECT_EQ(json["mean_return"], summary["final_eval"]["mean_return"]);
  EXPECT_EQ(json["mean_success"], summary["final_eval"]["mean_success"]);

  const RunResult table = RunCli("eval runs/tiny --checkpoint step_000000000150 --episodes 1", dir);
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("step 150"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("point-nav"), std::string::npos);

  // resuming a finished run is a no-op that says so
  const std::string finished = Slurp(dir / "runs/tiny/summary.json");
  const RunResult again = RunCli("train --resume runs/tiny", dir);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("finished at step 300; nothing to resume"), std::string::npos)
      << again.err;
  EXPECT_EQ(Slurp(dir / "runs/tiny/summary.json"), finished);
  fs::remove_all(dir);
}

TEST(CliTrainTest, StopAndResumeGiveTheUninterruptedNumbers) {
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "tiny.yaml") << kTinyConfig;
  ASSERT_EQ(RunCli("train tiny.yaml experiment.run_dir=full", dir).exit_code, 0);
  const RunResult stop = RunCli("train tiny.yaml experiment.run_dir=part --stop-after 150", dir);
  ASSERT_EQ(stop.exit_code, 0) << stop.err;
  EXPECT_NE(stop.err.find("--resume"), std::string::npos) << stop.err;
  EXPECT_FALSE(fs::exists(dir / "part/summary.json"));
  const RunResult resume = RunCli("train --resume part", dir);
  ASSERT_EQ(resume.exit_code, 0) << resume.err;
  auto evals = [&](const std::string& run) {
    std::ifstream in(dir / run / "eval.jsonl");
    std::string line, all;
    while (std::getline(in, line)) {
      auto row = nlohmann::json::parse(line);
      row.erase("wall_s");
      all += row.dump() + "\n";
    }
    return all;
  };
  EXPECT_EQ(evals("part"), evals("full"));
  const auto full = nlohmann::json::parse(RunCli("eval full --json", dir).out);
  const auto part = nlohmann::json::parse(RunCli("eval part --json", dir).out);
  EXPECT_EQ(full["per_task"], part["per_task"]);
  EXPECT_EQ(full["mean_return"], part["mean_return"]);
  fs::remove_all(dir);
}

// The last step in a run's metrics log, or -1.
int64_t LastLoggedStep(const fs::path& run) {
  int64_t last = -1;
  std::istringstream rows(Slurp(run / "metrics.jsonl"));
  for (std::string line; std::getline(rows, line);) {
    const auto row = nlohmann::json::parse(line, nullptr, false);
    if (row.is_object() && row.contains("step")) last = row["step"].get<int64_t>();
  }
  return last;
}

// Runs `manyworlds ARGS...` in `dir`, sends `signal` once the run's metrics
// log is past `after_step`, and returns the exit status (stderr to err.txt).
// Starts `manyworlds ARGS...` in `dir` (stderr to err.txt) and returns its pid.
pid_t StartCli(const fs::path& dir, const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (chdir(dir.c_str()) != 0 || !freopen("err.txt", "w", stderr)) _exit(99);
    std::vector<char*> argv;
    std::vector<std::string> all = {"manyworlds"};
    all.insert(all.end(), args.begin(), args.end());
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(MANYWORLDS_CLI_PATH, argv.data());
    _exit(98);
  }
  return pid;
}

int SignalDuringTraining(const fs::path& dir, const std::vector<std::string>& args,
                         const fs::path& run, int64_t after_step, int signal) {
  const pid_t pid = StartCli(dir, args);
  if (pid < 0) return -1;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (LastLoggedStep(run) <= after_step && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, signal);
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

// A run trained with its products on OpenBLAS and resumed on oneDNN (or the other way round)
// cannot repeat the uninterrupted numbers: resume says so, and still resumes.
TEST(CliTrainTest, ResumingOnAnotherGemmLibraryWarnsThatTheNumbersWillDiffer) {
  if (dlsym(RTLD_DEFAULT, "dnnl_sgemm") == nullptr) {
    GTEST_SKIP() << "this libtorch brings no oneDNN: every product runs on its BLAS";
  }
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "tiny.yaml") << kTinyConfig;
  setenv("MANYWORLDS_GEMM", "openblas", /*overwrite=*/1);
  const RunResult stop = RunCli("train tiny.yaml experiment.run_dir=part --stop-after 150", dir);
  unsetenv("MANYWORLDS_GEMM");
  ASSERT_EQ(stop.exit_code, 0) << stop.err;
  const RunResult resume = RunCli("train --resume part", dir);
  ASSERT_EQ(resume.exit_code, 0) << resume.err;
  EXPECT_NE(resume.err.find("written with products on 'blas', this program runs them on 'onednn'"),
            std::string::npos)
      << resume.err;
  EXPECT_TRUE(fs::exists(dir / "part/summary.json"));
  // the same library on both sides: no such warning
  ASSERT_EQ(RunCli("train tiny.yaml experiment.run_dir=same --stop-after 150", dir).exit_code, 0);
  const RunResult same = RunCli("train --resume same", dir);
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(same.err.find("written with products on"), std::string::npos) << same.err;
  fs::remove_all(dir);
}

// A signal while training: the iteration finishes, a checkpoint is written,
// the program exits with 128 + the signal, leaving no temporary file, and
// the run resumes from that checkpoint.
TEST(CliTrainTest, SignalsStopTrainingAtACheckpoint) {
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "tiny.yaml") << kTinyConfig;
  for (const int signal : {SIGINT, SIGTERM}) {
    const std::string name = "run" + std::to_string(signal);
    const fs::path run = dir / name;
    // no periodic checkpoint before step 100,000: the one found is the signal's
    int status = SignalDuringTraining(
        dir, {"train", "tiny.yaml", "experiment.steps_per_task=1000000",
              "experiment.checkpoint_every=100000", "experiment.run_dir=" + name},
        run, 400, signal);
    ASSERT_TRUE(WIFEXITED(status)) << "killed by the signal instead of stopping";
    EXPECT_EQ(WEXITSTATUS(status), 128 + signal);
    EXPECT_NE(Slurp(dir / "err.txt").find("interrupted"), std::string::npos) << Slurp(dir / "err.txt");
    // the last logged step has its checkpoint, and nothing temporary is left
    const int64_t last = LastLoggedStep(run);
    const std::string step = std::to_string(last);
    const std::string checkpoint = "step_" + std::string(12 - step.size(), '0') + step;
    EXPECT_TRUE(fs::exists(run / "checkpoints" / checkpoint / "state.json")) << checkpoint;
    for (const auto& entry : fs::recursive_directory_iterator(run)) {
      EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
    }
    // resumed there, and stopped the same way again
    status = SignalDuringTraining(dir, {"train", "--resume", name}, run, last + 100, signal);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + signal);
    EXPECT_NE(Slurp(dir / "err.txt").find("resuming " + name + " at step " + step),
              std::string::npos)
        << Slurp(dir / "err.txt");
    EXPECT_GT(LastLoggedStep(run), last);
  }
  fs::remove_all(dir);
}

// eval and `rollout --policy checkpoint:` read a run that is training, whose trainer prunes
// its old checkpoint (keep_checkpoints 1) right after writing a new one: a checkpoint that
// vanished after it was chosen is chosen again (3 of 10 tries used to fail, "cannot read
// .../state.json").
TEST(CliTrainTest, ReadingARunThatIsTrainingChoosesAgainWhenItsCheckpointIsPruned) {
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "tiny.yaml") << kTinyConfig;
  const pid_t trainer =
      StartCli(dir, {"train", "tiny.yaml", "experiment.steps_per_task=1000000",
                     "experiment.checkpoint_every=10", "experiment.keep_checkpoints=1",
                     "experiment.eval_every=0", "experiment.run_dir=live"});
  ASSERT_GT(trainer, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(dir / "live/checkpoints/latest") &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  for (int i = 0; i < 10; ++i) {
    const RunResult eval = RunCli("eval live --episodes 1 --json", dir);
    EXPECT_EQ(eval.exit_code, 0) << eval.err;
    const RunResult rollout = RunCli("rollout --policy checkpoint:live --episodes 1 --json", dir);
    EXPECT_EQ(rollout.exit_code, 0) << rollout.err;
  }
  kill(trainer, SIGTERM);
  int status = 0;
  waitpid(trainer, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGTERM) << Slurp(dir / "err.txt");
  fs::remove_all(dir);
}

// Sizes and step sizes that cannot work: one line that names the setting, before anything
// is allocated or trained (they ended in a 30-frame torch backtrace, or as the env's "action
// element 0 is -nan").
TEST(CliTrainTest, SizesAndStepSizesThatCannotWorkAreOneLineNamingTheSetting) {
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "tiny.yaml") << kTinyConfig;
  const RunResult batch = RunCli("train tiny.yaml agent.batch_size=100000000", dir);
  EXPECT_EQ(batch.exit_code, 2) << batch.err;
  EXPECT_TRUE(IsOneErrorLine(batch.err)) << batch.err;
  EXPECT_NE(batch.err.find("agent.batch_size"), std::string::npos) << batch.err;
  const std::string source = MANYWORLDS_TEST_SOURCE_DIR;
  // an allocation that fails inside libtorch (65536-wide layers under a 4 GB limit): one line
  // naming the settings that size memory, not libtorch's 30-frame backtrace
  const RunResult wide = test_support::RunProgram(
      "/bin/sh", "-c \"ulimit -v 4000000; '" + std::string(MANYWORLDS_CLI_PATH) + "' train " +
                     source + "/configs/point_nav_ppo.yaml agent.hidden_dim=65536 "
                     "experiment.run_dir=wide\"",
      dir);
  EXPECT_EQ(wide.exit_code, 1) << wide.err;
  EXPECT_TRUE(IsOneErrorLine(wide.err)) << wide.err;
  EXPECT_NE(wide.err.find("out of memory (you tried to allocate"), std::string::npos) << wide.err;
  EXPECT_NE(wide.err.find("agent.hidden_dim"), std::string::npos) << wide.err;
  for (const std::string& args :
       {"train " + source + "/configs/point_nav_maml.yaml agent.inner_lr=1e308",
        "train " + source + "/configs/point_nav_pearl.yaml agent.log_std_min=-1e308"}) {
    const RunResult r = RunCli(args + " experiment.steps_per_task=2000 experiment.run_dir=d" +
                                   std::to_string(args.size()),
                               dir);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.err;
    EXPECT_TRUE(IsOneErrorLine(r.err)) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("diverged"), std::string::npos) << args << "\n" << r.err;
  }
  fs::remove_all(dir);
}

TEST(CliTrainTest, BadInputGivesOneErrorLine) {
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "tiny.yaml") << kTinyConfig;
  struct Case {
    std::string args;
    int code;
    std::string needle;
  };
  const Case cases[] = {
      {"train", 2, "config file"},
      {"train missing.yaml", 2, "missing.yaml"},
      {"train tiny.yaml agent.hiden_dim=3", 2, "hidden_dim"},
      {"train tiny.yaml experiment.eval_episodes=0", 2, "eval_episodes"},
      {"train tiny.yaml env.id=point-nva", 2, "point-nav"},
      {"train --resume nowhere", 2, "nowhere"},
      {"train tiny.yaml --resume nowhere", 2, "resume"},
      {"train tiny.yaml --restart", 2, "--resume"},
      {"eval nowhere", 2, "nowhere"},
      {"eval tiny.yaml", 2, "'tiny.yaml' is not a directory"},
      {"eval /dev/null", 2, "'/dev/null' is not a directory"},
      {"train tiny.yaml +env.options.max_episode_steps=0", 2, "[1, 1000000]"},
      {"bench agent --obs-dim 100000 --batch 1000000", 2, "GiB"},
      {"train tiny.yaml --print-config experiment.eval_episodes=0", 2, "eval_episodes"},
      {"train tiny.yaml --print-config agent.hiden_dim=3", 2, "hidden_dim"},
      {"train --resume runs/tiny --print-config", 2, "--print-config"},
      // the learners run on the CPU: a GPU request says why not, before anything is made
      {"train tiny.yaml agent.device=cuda", 2, "'agent.device' = 'cuda'"},
      {"train tiny.yaml agent.device=gpu", 2, "allowed: auto, cpu, cuda, cuda:N"},
      {"train tiny.yaml --print-config agent.device=cuda:x", 2, "agent.device"},
      {"bench agent --device cuda:0 --updates 1 --repeats 1", 2, "'--device' = 'cuda:0'"},
  };
  for (const auto& c : cases) {
    const RunResult r = RunCli(c.args, dir);
    EXPECT_EQ(r.exit_code, c.code) << c.args << "\n" << r.err;
    EXPECT_TRUE(IsOneErrorLine(r.err)) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.needle), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "runs"));  // nothing was created

  // --print-config: the resolved tree (file, overrides, defaults), and no run directory
  const RunResult printed = RunCli("train tiny.yaml --print-config experiment.seed=7", dir);
  ASSERT_EQ(printed.exit_code, 0) << printed.err;
  const nlohmann::json resolved = nlohmann::json::parse(printed.out);
  EXPECT_EQ(resolved["experiment"]["seed"], 7);
  EXPECT_EQ(resolved["experiment"]["run_dir"], "runs/tiny");
  EXPECT_EQ(resolved["replay"]["capacity"], 5000);  // the file
  EXPECT_EQ(resolved["meta_test"]["num_evals"], experiments::MetaTestConfig{}.num_evals);
  EXPECT_FALSE(fs::exists(dir / "runs"));

  ASSERT_EQ(RunCli("train tiny.yaml experiment.steps_per_task=150", dir).exit_code, 0);
  const RunResult twice = RunCli("train tiny.yaml", dir);
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("--resume"), std::string::npos) << twice.err;
  const RunResult no_such = RunCli("eval runs/tiny --checkpoint step_9", dir);
  EXPECT_EQ(no_such.exit_code, 2);
  EXPECT_NE(no_such.err.find("step_000000000150"), std::string::npos) << no_such.err;
  // a corrupt checkpoint: runtime error (1), one line, logs untouched
  const std::string metrics = Slurp(dir / "runs/tiny/metrics.jsonl");
  std::ofstream(dir / "runs/tiny/checkpoints/step_000000000150/learner.pt",
                std::ios::trunc) << "not a checkpoint";
  const std::string summary = Slurp(dir / "runs/tiny/summary.json");
  for (const char* args : {"eval runs/tiny", "train --resume runs/tiny"}) {
    // a finished run is not resumed at all: without its summary it is an unfinished one
    if (std::string(args).find("--resume") != std::string::npos) {
      fs::remove(dir / "runs/tiny/summary.json");
    }
    const RunResult r = RunCli(args, dir);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.err;
    EXPECT_TRUE(IsOneErrorLine(r.err)) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("learner.pt"), std::string::npos) << r.err;
  }
  EXPECT_EQ(Slurp(dir / "runs/tiny/metrics.jsonl"), metrics);
  EXPECT_FALSE(summary.empty());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace manyworlds

namespace manyworlds {
namespace {

// eval CONFIG --policy: a config's protocols scored with the envs' own policies.
TEST(CliTrainTest, EvalScoresAConfigsProtocolsWithTheEnvsOwnPolicies) {
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "ml10.yaml") << "env: {id: ml10, options: {split: train}}\n"
                                      "eval_env: {options: {split: test}}\n";
  std::ofstream(dir / "mt10.yaml") << "env: {id: mt10, variations_per_task: 1}\n";
  const std::string meta = " --protocol meta-test --meta-batch-size 5 --total-tasks-per-cls 1 "
                           "--num-evals 1 --adaptation-episodes 1 --evaluation-episodes 1 --json";
  const RunResult scripted = RunCli("eval ml10.yaml --policy scripted" + meta, dir);
  ASSERT_EQ(scripted.exit_code, 0) << scripted.err;
  const auto s = nlohmann::json::parse(scripted.out);
  EXPECT_EQ(s["policy"], "scripted");
  EXPECT_EQ(s["meta_test"]["success_rate"], 1.0) << scripted.out;  // the experts solve ML10
  EXPECT_EQ(s["meta_test"]["per_task"].size(), 5u);
  const RunResult random = RunCli("eval ml10.yaml --policy random --seed 4" + meta, dir);
  ASSERT_EQ(random.exit_code, 0) << random.err;
  const auto r = nlohmann::json::parse(random.out);
  EXPECT_LT(r["meta_test"]["success_rate"].get<double>(), 0.5) << random.out;
  // the same seed, the same episodes; the multi-task protocol on the training tasks
  auto again = nlohmann::json::parse(RunCli("eval ml10.yaml --policy random --seed 4" + meta, dir).out);
  again["meta_test"].erase("wall_s");
  auto first = r;
  first["meta_test"].erase("wall_s");
  EXPECT_EQ(again, first);
  const RunResult multi = RunCli("eval mt10.yaml --policy scripted --episodes 1 --json", dir);
  ASSERT_EQ(multi.exit_code, 0) << multi.err;
  EXPECT_EQ(nlohmann::json::parse(multi.out)["mean_success"], 1.0) << multi.out;
  struct Case {
    std::string args;
    std::string needle;
  };
  const Case cases[] = {
      {"eval ml10.yaml --policy expert", "scripted"},
      {"eval runs/none --seed 3", "--seed is for --policy"},
      {"eval mt10.yaml --policy scripted --protocol meta-test", "no eval_env"},
      {"eval ml10.yaml --policy scripted --checkpoint step_1", "--checkpoint needs a run"},
  };
  for (const auto& c : cases) {
    const RunResult bad = RunCli(c.args, dir);
    EXPECT_EQ(bad.exit_code, 2) << c.args << "\n" << bad.err;
    EXPECT_TRUE(IsOneErrorLine(bad.err)) << c.args << "\n" << bad.err;
    EXPECT_NE(bad.err.find(c.needle), std::string::npos) << c.args << "\n" << bad.err;
  }
  fs::remove_all(dir);
}

TEST(CliTrainTest, StudyHelpAndBadArgumentsGiveOneErrorLine) {
  const fs::path dir = ScratchDir();
  const RunResult help = RunCli("study boxworld --help", dir);
  EXPECT_EQ(help.exit_code, 0);
  for (const char* option : {"--task", "--budget", "--methods", "--out", "--hide-target",
                             "--distribution", "--seed"}) {
    EXPECT_NE(help.out.find(option), std::string::npos) << option;
  }
  const RunResult task = RunCli("study boxworld --task medium", dir);
  EXPECT_EQ(task.exit_code, 2);
  EXPECT_TRUE(IsOneErrorLine(task.err)) << task.err;
  EXPECT_NE(task.err.find("--task must be simple or complex, got 'medium'"), std::string::npos)
      << task.err;
  const RunResult methods = RunCli("study boxworld --methods oracle,mamll", dir);
  EXPECT_EQ(methods.exit_code, 2);
  EXPECT_TRUE(IsOneErrorLine(methods.err)) << methods.err;
  EXPECT_NE(methods.err.find("unknown method 'mamll' (did you mean 'maml'?)"), std::string::npos)
      << methods.err;
  const RunResult budget = RunCli("study boxworld --budget 0", dir);
  EXPECT_EQ(budget.exit_code, 2);
  EXPECT_TRUE(IsOneErrorLine(budget.err)) << budget.err;
  EXPECT_FALSE(fs::exists(dir / "runs"));  // nothing created
  fs::remove_all(dir);
}

TEST(CliTrainTest, AlgorithmErrorsAreOneLineWithExitCode2) {
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "tiny.yaml") << kTinyConfig;
  // an unknown algorithm names the valid ones
  RunResult r = RunCli("train tiny.yaml agent.algo=ppx", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(IsOneErrorLine(r.err)) << r.err;
  EXPECT_NE(r.err.find("sac, ppo, trpo"), std::string::npos) << r.err;
  // a continuous-only algorithm on a Discrete env
  r = RunCli("train tiny.yaml env.id=cartpole env.options={}", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(IsOneErrorLine(r.err)) << r.err;
  EXPECT_NE(r.err.find("Discrete"), std::string::npos) << r.err;
  // a key of another algorithm
  r = RunCli("train tiny.yaml agent.algo=ppo", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(IsOneErrorLine(r.err)) << r.err;
  EXPECT_NE(r.err.find("agent.batch_size"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "runs" / "tiny"));
}

TEST(CliTrainTest, PpoTrainsEvaluatesAndResumesFromTheCommandLine) {
  const fs::path dir = ScratchDir();
  const std::string config = std::string(MANYWORLDS_TEST_SOURCE_DIR) + "/configs/cartpole_ppo.yaml";
  const std::string args = "'" + config + "' experiment.steps_per_task=1500 " +
                           "experiment.eval_every=500 experiment.checkpoint_every=500 " +
                           "experiment.run_dir=runs/ppo";
  RunResult r = RunCli("train " + args + " --stop-after 500", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunCli("train --resume runs/ppo", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("cartpole/3"), std::string::npos) << r.out;
  r = RunCli("eval runs/ppo --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["step"], 1500);
  EXPECT_EQ(json["per_task"].size(), 4u);
  EXPECT_TRUE(fs::exists(dir / "runs" / "ppo" / "summary.json"));

  // the trained policy through `rollout --policy checkpoint:RUN_DIR`: per-episode
  // records whose means are eval's for the same seed
  r = RunCli("rollout --policy checkpoint:runs/ppo --episodes 2 --seed 5 --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rollout = nlohmann::json::parse(r.out);
  EXPECT_EQ(rollout["step"], 1500);
  ASSERT_EQ(rollout["tasks"].size(), 4u);
  for (const auto& task : rollout["tasks"]) {
    ASSERT_EQ(task["episodes"].size(), 2u);
    const double mean = (task["episodes"][0]["return"].get<double>() +
                         task["episodes"][1]["return"].get<double>()) / 2;
    EXPECT_NEAR(task["mean_return"].get<double>(), mean, 1e-9);
  }
  EXPECT_EQ(RunCli("rollout --policy checkpoint:runs/ppo --episodes 2 --seed 5 --json", dir).out,
            r.out);  // seeded
  r = RunCli("rollout --policy checkpoint:runs/ppo/checkpoints/step_000000001500 --episodes 1",
             dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("cartpole/3"), std::string::npos) << r.out;
  r = RunCli("rollout --policy checkpoint:runs/ppo --env point-nav", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(IsOneErrorLine(r.err)) << r.err;
  EXPECT_NE(r.err.find("cartpole"), std::string::npos) << r.err;
  r = RunCli("rollout --policy checkpoint:runs/missing", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(IsOneErrorLine(r.err)) << r.err;
}

TEST(CliTrainTest, Rl2MetaTestAndBanditBaselinesFromTheCommandLine) {
  const fs::path dir = ScratchDir();
  const std::string config = std::string(MANYWORLDS_TEST_SOURCE_DIR) + "/configs/bandit_rl2.yaml";
  RunResult r = RunCli("train '" + config + "' experiment.steps_per_task=200 " +
                           "experiment.run_dir=runs/rl2 meta_test.trials_per_task=20",
                       dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("meta-test: per_variation: 20 trials per task"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("meta-train: per_variation: 20 trials per task"), std::string::npos) << r.out;
  r = RunCli("eval runs/rl2 --protocol meta-test --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto json = nlohmann::json::parse(r.out)["meta_test"];
  for (const char* key : {"success_rate", "per_task", "pre_adaptation_success_rate",
                          "trial_return"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  // the same trials as the run's own final meta-test
  const auto summary = nlohmann::json::parse(Slurp(dir / "runs" / "rl2" / "summary.json"));
  EXPECT_DOUBLE_EQ(json["trial_return"].get<double>(),
                   summary["final_meta_test"]["trial_return"].get<double>());
  // meta-train: the same protocol on the training bandits, as logged in training
  r = RunCli("eval runs/rl2 --protocol meta-train --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto train = nlohmann::json::parse(r.out)["meta_train"];
  EXPECT_EQ(train["trials_per_task"], 20);
  EXPECT_DOUBLE_EQ(train["trial_return"].get<double>(),
                   summary["final_meta_train"]["trial_return"].get<double>());
  EXPECT_NE(train["trial_return"], json["trial_return"]);
  EXPECT_TRUE(fs::exists(dir / "runs" / "rl2" / "meta_train.jsonl"));
  // resuming the finished meta-RL run keeps its meta-test results (it wrote them as null)
  const std::string finished = Slurp(dir / "runs" / "rl2" / "summary.json");
  r = RunCli("train --resume runs/rl2", dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Slurp(dir / "runs" / "rl2" / "summary.json"), finished);
  // the protocol's parameters on the command line: fewer trials give other numbers
  r = RunCli("eval runs/rl2 --protocol meta-test --trials-per-task 5 --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["meta_test"]["trials_per_task"], 5);
  for (const char* bad : {"--protocol meta-test --num-evals abc",
                          "--protocol meta-test --meta-protocol v3", "--num-evals 2"}) {
    r = RunCli(std::string("eval runs/rl2 ") + bad, dir);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_TRUE(IsOneErrorLine(r.err)) << bad << ": " << r.err;
  }
  // eval --help names v3's parameters
  r = RunCli("eval --help", dir);
  for (const char* option : {"--num-evals", "--adaptation-steps", "--adaptation-episodes",
                             "--evaluation-episodes", "--meta-batch-size", "--total-tasks-per-cls",
                             "--task-select", "--terminate-on-success", "metalearning_evaluation"}) {
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
  }
  r = RunCli("baselines bandit runs/rl2 --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto baselines = nlohmann::json::parse(r.out);
  EXPECT_EQ(baselines["tasks"], 200);  // the held-out bandits
  EXPECT_EQ(baselines["baselines"].size(), 4u);
  // rollout of a meta-learner: whole trials on held-out bandits, one row per
  // episode (bandit_rl2: no exploration phase, 10 evaluation pulls)
  r = RunCli("rollout --policy checkpoint:runs/rl2 --episodes 3 --json", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rollout = nlohmann::json::parse(r.out);
  ASSERT_EQ(rollout["episodes"].size(), 3u * 10u);
  for (const auto& e : rollout["episodes"]) EXPECT_EQ(e["phase"], "evaluation");
  r = RunCli("rollout --policy checkpoint:runs/rl2 --episodes 1", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("after adaptation"), std::string::npos) << r.out;
  // a run without held-out tasks, and a multi-task-only flag
  ASSERT_EQ(RunCli("train '" + config + "' experiment.steps_per_task=20 eval_env=null " +
                       "experiment.run_dir=runs/plain",
                   dir)
                .exit_code,
            0);
  for (const std::string& bad : {std::string("eval runs/plain --protocol meta-test"),
                                 std::string("eval runs/rl2 --protocol meta-test --episodes 2"),
                                 std::string("eval runs/rl2 --protocol meta"),
                                 std::string("eval runs/plain --protocol meta-train"),
                                 std::string("baselines bandit runs/nothing")}) {
    r = RunCli(bad, dir);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_TRUE(IsOneErrorLine(r.err)) << bad << ": " << r.err;
  }
}

// `bench agent` times every registered algorithm through its registry row,
// and names them all when asked for another.
TEST(CliTrainTest, BenchAgentRunsEveryRegisteredAlgorithm) {
  const fs::path dir = ScratchDir();
  for (const experiments::AlgorithmInfo& info : experiments::Algorithms()) {
    const RunResult r = RunCli("bench agent --algo " + info.name +
                                   " --json --hidden 16 --layers 1 --batch 32 --minibatch 16"
                                   " --trial-length 20 --frame 24 --updates 1 --repeats 1",
                               dir);
    ASSERT_EQ(r.exit_code, 0) << info.name << "\n" << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.at("agent"), info.name);
    const double rate = j.contains("updates_per_s") ? j["updates_per_s"].get<double>()
                                                    : j.at("samples_per_s").get<double>();
    EXPECT_GT(rate, 0.0) << info.name;
    EXPECT_TRUE(j.contains("unit") || j.contains("samples")) << info.name;
  }
  const RunResult bad = RunCli("bench agent --algo te-ppo", dir);
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_TRUE(IsOneErrorLine(bad.err)) << bad.err;
  EXPECT_NE(bad.err.find("--algo: unknown algorithm 'te-ppo'"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("allowed: " + experiments::AlgorithmNames()), std::string::npos)
      << bad.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace manyworlds
