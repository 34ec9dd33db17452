// Runs the built `manyworlds` binary (MANYWORLDS_CLI_PATH) as a user would.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "manyworlds/config/yaml.h"
#include "tests/support/child_cases.h"
#include "tests/support/cli_runner.h"
#include "tests/support/scratch_dir.h"

namespace manyworlds {
namespace {

namespace fs = std::filesystem;

using test_support::IsOneErrorLine;
using test_support::RunResult;
using test_support::Slurp;

// Runs `manyworlds <args>` in `cwd`.
RunResult RunCli(const std::string& args, const fs::path& cwd = fs::temp_directory_path()) {
  return test_support::RunProgram(MANYWORLDS_CLI_PATH, args, cwd);
}

fs::path ScratchDir() {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  return test_support::ScratchDir("cli", info->name(), /*create=*/true);
}

// The training commands need libtorch; the program is also built without it
// (MANYWORLDS_WITH_TORCH=OFF, as scripts/sanitize.sh does).
#ifdef MANYWORLDS_CLI_HAS_TRAINING
constexpr bool kHasTrainingCommands = true;
#else
constexpr bool kHasTrainingCommands = false;
#endif
constexpr const char* kTrainingCommands[] = {"train", "eval", "study"};

TEST(CliTest, HelpExitsZeroEverywhere) {
  std::vector<std::string> commands = {"--help", "envs --help", "rollout --help",
                                       "check-env --help", "bench --help", "bench env --help",
                                       "demo --help", "export-xml --help", "render --help",
                                       "baselines --help"};
  if (kHasTrainingCommands) {
    for (const char* c : kTrainingCommands) commands.push_back(std::string(c) + " --help");
  }
  for (const std::string& args : commands) {
    const RunResult r = RunCli(args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << args;
  }
}

// Without libtorch the training commands are absent, and saying so is a usage
// error like any unknown command, never a crash.
TEST(CliTest, TrainingCommandsExistExactlyWhenBuiltWithLibtorch) {
  const RunResult help = RunCli("--help");
  ASSERT_EQ(help.exit_code, 0) << help.err;
  for (const char* c : kTrainingCommands) {
    const std::string line = "  " + std::string(c) + " ";
    EXPECT_EQ(help.out.find(line) != std::string::npos, kHasTrainingCommands) << c;
    const RunResult r = RunCli(std::string(c) + " --help");
    if (kHasTrainingCommands) {
      EXPECT_EQ(r.exit_code, 0) << c << "\n" << r.err;
    } else {
      EXPECT_EQ(r.exit_code, 2) << c;
      EXPECT_TRUE(IsOneErrorLine(r.err)) << r.err;
      EXPECT_NE(r.err.find("unknown command '" + std::string(c) + "'"), std::string::npos)
          << r.err;
    }
  }
}

// The top-level help names every algorithm that `agent.algo` accepts: the list the
// registry's own error message gives.
TEST(CliTest, HelpNamesEveryRegisteredAlgorithm) {
  if (!kHasTrainingCommands) GTEST_SKIP() << "built without libtorch: no train command";
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "bad.yaml") << "agent:\n  algo: no_such_algorithm\n";
  const RunResult bad = RunCli("train bad.yaml", dir);
  EXPECT_NE(bad.exit_code, 0);
  const size_t at = bad.err.find("allowed: ");
  ASSERT_NE(at, std::string::npos) << bad.err;
  std::string allowed = bad.err.substr(at + 9);
  allowed = allowed.substr(0, allowed.find_first_of("\n"));
  EXPECT_NE(allowed.find("maml"), std::string::npos) << allowed;
  EXPECT_NE(allowed.find("pearl"), std::string::npos) << allowed;
  const RunResult help = RunCli("--help");
  ASSERT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("(agent.algo: " + allowed + ")"), std::string::npos)
      << "allowed: " << allowed << "\n" << help.out;
}

TEST(CliTest, EnvsListsTheClassicSuite) {
  const RunResult r = RunCli("envs --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto envs = nlohmann::json::parse(r.out);
  ASSERT_TRUE(envs.is_array());
  bool found = false;
  for (const auto& e : envs) {
    if (e["id"] != "cartpole") continue;
    found = true;
    EXPECT_EQ(e["family"], "classic");
    EXPECT_TRUE(e["max_episode_steps"].is_number_integer());
    EXPECT_FALSE(e["options"].empty());
    EXPECT_TRUE(e["options"][0].contains("default"));
  }
  EXPECT_TRUE(found);
  EXPECT_EQ(RunCli("envs").exit_code, 0);
}

TEST(CliTest, UnknownEnvSuggestsTheNearestId) {
  const RunResult r = RunCli("rollout --env cartpol");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(IsOneErrorLine(r.err)) << r.err;
  EXPECT_NE(r.err.find("did you mean 'cartpole'"), std::string::npos) << r.err;
  EXPECT_EQ(RunCli("check-env --env cartpol").exit_code, 2);
  EXPECT_EQ(RunCli("bench env --env cartpol").exit_code, 2);
}

TEST(CliTest, BadInputIsAUsageError) {
  for (const char* args :
       {"rollout --env bandit --option n_armz=3", "rollout --env bandit --option n_arms",
        "rollout --env bandit --option n_arms=many", "rollout --env cartpole --policy scripted",
        "rollout --env cartpole --episodes 0", "rollout --env cartpole --seed -1",
        "rollout --env cartpole --frobnicate", "rollout --env cartpole --policy expert",
        "export-xml --env cartpole --out x.xml", "export-xml --env reach",
        "render --env cartpole --out x.png",
        "rollout", "frobnicate", "", "bench", "demo nonexistent.yaml",
        "demo --out x episdoes=3", "demo --out x episodes=ten", "demo --out x envs=[cartpol]"}) {
    const RunResult r = RunCli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_TRUE(IsOneErrorLine(r.err)) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
  }
  const RunResult option = RunCli("rollout --env bandit --option n_armz=3");
  EXPECT_NE(option.err.find("did you mean 'n_arms'"), std::string::npos) << option.err;
  EXPECT_NE(RunCli("rollout --env cartpole --policy scripted").err.find("no scripted policy"),
            std::string::npos);
  EXPECT_NE(RunCli("rollout --env cartpole --policy expert").err.find("allowed: random, scripted"),
            std::string::npos);
  EXPECT_NE(RunCli("demo --out x episdoes=3").err.find("did you mean 'episodes'"),
            std::string::npos);
}

TEST(CliTest, OutputThatCannotBeWrittenIsAnError) {
  // /dev/full: every write fails (ENOSPC); the program must not exit 0 with its output lost
  for (const char* args : {"envs > /dev/full", "rollout --env cartpole --json > /dev/full",
                           "--help > /dev/full", "rollout --env bandit --option "
                           "n_arms=[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]] > /dev/full"}) {
    const RunResult r = RunCli(args);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_TRUE(IsOneErrorLine(r.err)) << args << "\n" << r.err;
  }
  EXPECT_NE(RunCli("envs > /dev/full").err.find("error: cannot write standard output"),
            std::string::npos);
  // past a file-size limit (ulimit -f 1): one line, not death by SIGXFSZ (exit 153)
  const fs::path dir = ScratchDir();
  const RunResult limited = test_support::RunProgram(
      "/bin/sh", "-c \"ulimit -f 1; '" + std::string(MANYWORLDS_CLI_PATH) +
                     "' rollout --env cartpole --episodes 50 --json > out.json\"", dir);
  EXPECT_EQ(limited.exit_code, 1) << limited.err;
  EXPECT_TRUE(IsOneErrorLine(limited.err)) << limited.err;
  EXPECT_NE(limited.err.find("File too large"), std::string::npos) << limited.err;
  fs::remove_all(dir);
}

// Counts come from one place (core/limits.h) and memory is estimated before envs are made:
// typos of 10^8 envs or 10^9 threads are one line, not 0.5 GB/s of growth or an abort.
TEST(CliTest, CountsMemoryAndThreadsThatCannotWorkAreOneErrorLine) {
  for (const char* args :
       {"bench env --env cartpole --num-envs 100000000", "bench env --env cartpole --threads 300",
        "rollout --env cartpole --threads 1000000000"}) {
    const RunResult r = RunCli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_TRUE(IsOneErrorLine(r.err)) << args << "\n" << r.err;
  }
  EXPECT_NE(RunCli("bench env --env cartpole --num-envs 100000000").err.find("[1, 65536]"),
            std::string::npos);
  if (test_support::kAddressSanitizer) GTEST_SKIP() << "ulimit -v: ASan reserves terabytes";
  const fs::path dir = ScratchDir();
  // 60,000 manipulation envs under a 3 GB address-space limit: refused after the first few
  // are made, from their measured size
  const RunResult envs = test_support::RunProgram(
      "/bin/sh", "-c \"ulimit -v 3000000; '" + std::string(MANYWORLDS_CLI_PATH) +
                     "' bench env --env reach --num-envs 60000 --steps 10 --repeats 1\"", dir);
  EXPECT_EQ(envs.exit_code, 2) << envs.err;
  EXPECT_TRUE(IsOneErrorLine(envs.err)) << envs.err;
  EXPECT_NE(envs.err.find("60000 envs needs about"), std::string::npos) << envs.err;
  EXPECT_NE(envs.err.find("ulimit"), std::string::npos) << envs.err;
  // threads the system will not start: one line (it was "terminate called without an active
  // exception", SIGABRT)
  const RunResult threads = test_support::RunProgram(
      "/bin/sh", "-c \"ulimit -v 1500000; '" + std::string(MANYWORLDS_CLI_PATH) +
                     "' rollout --env cartpole --episodes 300 --threads 256\"", dir);
  if (threads.err.find("error while loading shared libraries") != std::string::npos) {
    // a CUDA libtorch's libraries alone take more address space than the limit
    fs::remove_all(dir);
    GTEST_SKIP() << "the program cannot load under ulimit -v 1500000: " << threads.err;
  }
  EXPECT_EQ(threads.exit_code, 1) << threads.err;
  EXPECT_TRUE(IsOneErrorLine(threads.err)) << threads.err;
  EXPECT_NE(threads.err.find("cannot start thread"), std::string::npos) << threads.err;
  fs::remove_all(dir);
}

// Options that were accepted and then misbehaved: the reward scale of the recurrent
// observation put inf into observations; --steps past the episode rendered its last frame
TEST(CliTest, OptionsOutsideTheirRangeAreRefusedBeforeAnythingRuns) {
  const RunResult scale =
      RunCli("rollout --env point-nav --option recurrent_meta_obs=true "
             "--option recurrent_meta_obs_reward_scale=1e308");
  EXPECT_EQ(scale.exit_code, 2) << scale.err;
  EXPECT_NE(scale.err.find("outside [-1000, 1000]"), std::string::npos) << scale.err;
  const fs::path dir = ScratchDir();
  const RunResult render = RunCli("render --env reach --steps 1000000000 --out x.png", dir);
  EXPECT_EQ(render.exit_code, 2) << render.err;
  EXPECT_NE(render.err.find("past the end of the episode of 'reach' (500 steps)"), std::string::npos)
      << render.err;
  EXPECT_FALSE(fs::exists(dir / "x.png"));
  fs::remove_all(dir);
}

TEST(CliTest, RolloutJsonIsByteIdenticalAcrossRuns) {
  const std::string args =
      "rollout --env point-nav --episodes 3 --seed 5 --task-seed 7 --option max_episode_steps=50 "
      "--json";
  const RunResult a = RunCli(args);
  const RunResult b = RunCli(args);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
  const auto summary = nlohmann::json::parse(a.out);
  ASSERT_EQ(summary["episodes"].size(), 3u);
  EXPECT_EQ(summary["episodes"][0]["length"], 50);
  EXPECT_TRUE(summary.contains("mean_return"));
  EXPECT_TRUE(summary.contains("success_rate"));
  EXPECT_NE(RunCli("rollout --env point-nav --episodes 3 --seed 6 --json").out, a.out);
}

TEST(CliTest, RolloutJsonIsByteIdenticalAcrossThreadCounts) {
  // Every episode is seeded from its index, so threads only change who runs it.
  for (const std::string env : {"acrobot --episodes 5", "point-nav --episodes 7",
                                "mt10 --policy random --episodes 1"}) {
    const std::string args = "rollout --env " + env + " --seed 3 --task-seed 4 --json";
    const RunResult one = RunCli(args + " --threads 1");
    ASSERT_EQ(one.exit_code, 0) << one.err;
    for (const char* threads : {" --threads 2", " --threads 3"}) {
      const RunResult many = RunCli(args + threads);
      ASSERT_EQ(many.exit_code, 0) << many.err;
      EXPECT_EQ(one.out, many.out) << env << threads;
    }
  }
  // Episodes differ from one another (each has its own env seed).
  const auto j = nlohmann::json::parse(RunCli("rollout --env point-nav --episodes 2 --json").out);
  EXPECT_NE(j["episodes"][0], j["episodes"][1]);
  EXPECT_NE(RunCli("rollout --env cartpole --threads 0").exit_code, 0);
}

TEST(CliTest, ScriptedRolloutOverABenchmarkReportsEveryTask) {
  const std::string args = "rollout --env mt1 --option task=reach --policy scripted --episodes 5 --json";
  const RunResult a = RunCli(args);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_EQ(a.out, RunCli(args).out);
  const auto j = nlohmann::json::parse(a.out);
  ASSERT_EQ(j["per_task"].size(), 1u);
  EXPECT_EQ(j["per_task"][0]["task"], "reach");
  EXPECT_EQ(j["per_task"][0]["episodes"], 5);
  EXPECT_EQ(j["episodes"].size(), 5u);
  EXPECT_GE(j["success_rate"].get<double>(), 0.8);
}

// render records the first episode rollout runs with the same seeds: the
// random policy's actions, hence the return, are the same.
TEST(CliTest, RenderRecordsTheFirstEpisodeOfRollout) {
  const fs::path dir = ScratchDir();
  const std::string seeds = " --env reach --policy random --seed 9 --task-seed 2";
  const RunResult render =
      RunCli("render" + seeds + " --steps 500 --width 32 --height 24 --out f.png", dir);
  ASSERT_EQ(render.exit_code, 0) << render.err;
  const RunResult rollout = RunCli("rollout" + seeds + " --episodes 1 --json");
  ASSERT_EQ(rollout.exit_code, 0) << rollout.err;
  const double expected = nlohmann::json::parse(rollout.out)["episodes"][0]["return"];
  char formatted[64];
  std::snprintf(formatted, sizeof(formatted), "return %.2f,", expected);
  EXPECT_NE(render.out.find(formatted), std::string::npos) << render.out << " vs " << formatted;
}

TEST(CliTest, ExportXmlWritesALoadableModel) {
  const fs::path dir = ScratchDir();
  const RunResult r = RunCli("export-xml --env pick-place --task-seed 4 --out v.xml", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string xml = Slurp(dir / "v.xml");
  EXPECT_NE(xml.find("<mujoco"), std::string::npos);
  EXPECT_NE(xml.find("name=\"obj\""), std::string::npos);
  EXPECT_EQ(xml.find("<include"), std::string::npos);  // self-contained
  // never written over a device, a directory or a link: one error line, exit 1
  fs::create_directories(dir / "sub");
  for (const char* target : {"/dev/null", "sub"}) {
    const RunResult refused =
        RunCli(std::string("export-xml --env reach --out ") + target, dir);
    EXPECT_EQ(refused.exit_code, 1) << target;
    EXPECT_NE(refused.err.find("not a regular file"), std::string::npos) << refused.err;
  }
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_TRUE(fs::is_directory(dir / "sub"));
}

// Every MuJoCo env renders and exports, the half-cheetah included (from its
// tracking camera by default); other envs get one error line that says which
// envs do.
TEST(CliTest, RenderAndExportXmlWorkForTheHalfCheetah) {
  const fs::path dir = ScratchDir();
  const RunResult png = RunCli(
      "render --env half-cheetah-vel --policy random --steps 5 --width 32 --height 24 --out c.png",
      dir);
  ASSERT_EQ(png.exit_code, 0) << png.err;
  EXPECT_NE(png.out.find("1 frame 32x24 from camera track after 5 steps"), std::string::npos)
      << png.out;
  EXPECT_EQ(Slurp(dir / "c.png").substr(1, 3), "PNG");
  const RunResult mp4 = RunCli(
      "render --env half-cheetah-dir --policy random --steps 6 --every 3 --width 32 --height 24 "
      "--out c.mp4",
      dir);
  ASSERT_EQ(mp4.exit_code, 0) << mp4.err;
  EXPECT_NE(mp4.out.find("3 frames 32x24 from camera track after 6 steps"), std::string::npos)
      << mp4.out;
  EXPECT_GT(fs::file_size(dir / "c.mp4"), 0u);

  const RunResult xml = RunCli("export-xml --env half-cheetah-vel --out h.xml", dir);
  ASSERT_EQ(xml.exit_code, 0) << xml.err;
  const std::string model = Slurp(dir / "h.xml");
  EXPECT_NE(model.find("<mujoco"), std::string::npos);
  EXPECT_NE(model.find("name=\"torso\""), std::string::npos);

  for (const char* args : {"render --env cartpole --out x.png",
                           "render --env cartpole --policy random --out x.png",
                           "export-xml --env cartpole --out x.xml"}) {
    const RunResult refused = RunCli(args, dir);
    EXPECT_EQ(refused.exit_code, 2) << args;
    EXPECT_TRUE(IsOneErrorLine(refused.err)) << refused.err;
    EXPECT_NE(refused.err.find("env 'cartpole' has no MuJoCo scene"), std::string::npos)
        << refused.err;
    EXPECT_NE(refused.err.find("half-cheetah"), std::string::npos) << refused.err;
  }
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

TEST(CliTest, RenderExportXmlAndRolloutWorkForTheDmcSuite) {
  const fs::path dir = ScratchDir();
  // the default camera is each model's first, placed as dm_control's camera 0
  for (const auto& [id, camera] : {std::pair{"dmc-finger-spin", "fixed"},
                                   std::pair{"hipbmdp-walker-walk-friction", "side"}}) {
    const RunResult png = RunCli(std::string("render --env ") + id +
                                     " --policy random --steps 3 --width 32 --height 24 --out d.png",
                                 dir);
    ASSERT_EQ(png.exit_code, 0) << png.err;
    EXPECT_NE(png.out.find(std::string("from camera ") + camera + " after 3 steps"),
              std::string::npos)
        << png.out;
    EXPECT_EQ(Slurp(dir / "d.png").substr(1, 3), "PNG");
  }
  // a variant's MJCF holds its parameter: task seed 0 draws variant 6, torso half-length 1.1
  const RunResult xml =
      RunCli("export-xml --env hipbmdp-cheetah-run-torso-length --task-seed 0 --out c.xml", dir);
  ASSERT_EQ(xml.exit_code, 0) << xml.err;
  EXPECT_NE(xml.out.find("\"variant\":6"), std::string::npos) << xml.out;
  EXPECT_NE(Slurp(dir / "c.xml").find("fromto=\"-1.1 0 0 1.1 0 0\""), std::string::npos);
  // MTRL's finger split: one episode per evaluation group, 1000 steps each
  const RunResult rollout = RunCli(
      "rollout --env hipbmdp-finger-spin-size --option split=mtrl --episodes 1 --json", dir);
  ASSERT_EQ(rollout.exit_code, 0) << rollout.err;
  for (const char* group : {"\"train\"", "\"interpolation\"", "\"extrapolation\""}) {
    EXPECT_NE(rollout.out.find(group), std::string::npos) << group << rollout.out;
  }
}

TEST(CliTest, PixelObservationsSayWhatRenderedThemOrWhyNot) {
  const RunResult ok = RunCli(
      "rollout --env dmc-cheetah-run --option obs=pixels --option pixel_width=16 "
      "--option pixel_height=16 --option max_episode_steps=3 --episodes 1");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.err.find("pixel observations 3x16x16 from camera 'side', rendered with OSMesa"),
            std::string::npos)
      << ok.err;
  // a machine whose OSMesa cannot render (Mesa crashes with this driver; the renderer refuses
  // it first): one line naming the backend, no crash
  setenv("GALLIUM_DRIVER", "zink", 1);
  const RunResult refused = RunCli("rollout --env reach --option obs=pixels --episodes 1");
  unsetenv("GALLIUM_DRIVER");
  EXPECT_EQ(refused.exit_code, 1) << refused.err;
  EXPECT_TRUE(IsOneErrorLine(refused.err)) << refused.err;
  EXPECT_NE(refused.err.find("OSMesa"), std::string::npos) << refused.err;
  // the EGL backend, chosen at run time (here Mesa's software EGL device: the same rasteriser as
  // OSMesa, so the same image, byte for byte)
  const fs::path dir = ScratchDir();
  const std::string render =
      "render --env dmc-cheetah-run --policy random --steps 5 --width 64 --height 48 --out ";
  ASSERT_EQ(RunCli(render + "osmesa.png", dir).exit_code, 0);
  setenv("MANYWORLDS_GL", "egl", 1);
  const RunResult egl = RunCli(render + "egl.png", dir);
  const RunResult egl_rollout = RunCli(
      "rollout --env reach --option obs=pixels --option max_episode_steps=2 --episodes 1");
  setenv("MANYWORLDS_GL", "vulkan", 1);
  const RunResult unknown = RunCli("rollout --env reach --option obs=pixels --episodes 1");
  unsetenv("MANYWORLDS_GL");
  ASSERT_EQ(egl.exit_code, 0) << egl.err;
  EXPECT_EQ(Slurp(dir / "egl.png"), Slurp(dir / "osmesa.png"));
  ASSERT_EQ(egl_rollout.exit_code, 0) << egl_rollout.err;
  EXPECT_NE(egl_rollout.err.find("rendered with EGL"), std::string::npos) << egl_rollout.err;
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_TRUE(IsOneErrorLine(unknown.err)) << unknown.err;
  EXPECT_NE(unknown.err.find("allowed: osmesa"), std::string::npos) << unknown.err;
  // envs without a scene: a configuration error
  const RunResult classic = RunCli("rollout --env cartpole --option obs=pixels");
  EXPECT_EQ(classic.exit_code, 2) << classic.err;
  EXPECT_NE(classic.err.find("no MuJoCo scene"), std::string::npos) << classic.err;
}

TEST(CliTest, CheckEnvPassesOnCartpole) {
  const RunResult r = RunCli("check-env --env cartpole");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("checks passed"), std::string::npos);
  const RunResult j = RunCli("check-env --env cartpole --json");
  EXPECT_EQ(j.exit_code, 0);
  EXPECT_NO_THROW(nlohmann::json::parse(j.out));
}

TEST(CliTest, BenchReportsStepsPerSecond) {
  const RunResult r =
      RunCli("bench env --env cartpole --num-envs 2 --steps 2000 --repeats 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["steps_per_s"].get<double>(), 0.0);
  EXPECT_EQ(j["samples"].size(), 2u);
}

TEST(CliTest, DemoWritesReloadableResults) {
  const fs::path dir = ScratchDir();
  std::ofstream(dir / "demo.yaml") << "episodes: 2\nenvs: [cartpole, bandit]\nout_dir: out\n";
  const RunResult r = RunCli("demo demo.yaml seed=3 +unused=1", dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;  // '+' adds a key the demo does not know
  EXPECT_NE(r.err.find("unknown key 'unused'"), std::string::npos) << r.err;

  const RunResult ok = RunCli("demo demo.yaml seed=3 task_seed=4", dir);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("cartpole"), std::string::npos);
  for (const char* name : {"config.yaml", "results.json", "results.csv"}) {
    EXPECT_TRUE(fs::exists(dir / "out" / name)) << name;
  }
  const auto config = LoadYamlFile(dir / "out" / "config.yaml");
  EXPECT_EQ(config["seed"], 3);
  EXPECT_EQ(config["task_seed"], 4);
  EXPECT_EQ(config["episodes"], 2);
  EXPECT_EQ(config["envs"], nlohmann::json::parse(R"(["cartpole", "bandit"])"));
  const auto results = nlohmann::json::parse(Slurp(dir / "out" / "results.json"));
  EXPECT_EQ(results["results"].size(), 2u);
  EXPECT_EQ(results["config"], config);
  const std::string csv = Slurp(dir / "out" / "results.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);

  // the resolved config reruns as is, and --out wins over out_dir
  const RunResult again = RunCli("demo out/config.yaml --out out2", dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(LoadYamlFile(dir / "out2" / "config.yaml")["seed"], 3);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace manyworlds
