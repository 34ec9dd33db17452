// The box-world study (experiments/studies/boxworld_study.h) on a tiny budget: one
// row per method with finite numbers and the paper's column, resume without
// rerunning finished methods, and one-line errors for bad options.
#include "manyworlds/experiments/studies/boxworld_study.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "manyworlds/agents/ppo/ppo_config.h"
#include "manyworlds/core/error.h"
#include "tests/experiments/scratch_dirs.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

using test_dirs::SourceDir;
fs::path Scratch(const std::string& name) { return test_dirs::Scratch("study", name); }

StudyOptions Tiny(const std::string& name, std::vector<std::string> methods) {
  StudyOptions o;
  o.task = "simple";
  o.budget = 1e-6;  // every run rounds up to one training iteration
  o.methods = std::move(methods);
  o.out_dir = Scratch(name);
  o.config_dir = SourceDir() / "configs";
  o.seed = 3;
  return o;
}

TEST(BoxWorldStudyTest, TinyBudgetGivesOneFiniteRowPerMethodWithThePapersColumn) {
  const StudyOptions o = Tiny("rows", PaperMethods());
  const std::vector<StudyRow> rows = RunBoxWorldStudy(o);
  ASSERT_EQ(rows.size(), 6u);
  for (size_t i = 0; i < rows.size(); ++i) {
    const StudyRow& r = rows[i];
    EXPECT_EQ(r.method, PaperMethods()[i]);
    EXPECT_EQ(r.episodes, kTestLayouts * kQueryTargets) << r.method;
    EXPECT_TRUE(std::isfinite(r.mean_reward)) << r.method;
    EXPECT_TRUE(std::isfinite(r.std_reward) && r.std_reward >= 0) << r.method;
    EXPECT_GE(r.success, 0.0);
    EXPECT_LE(r.success, 1.0);
    // a return is the +100 (at most once: the episode ends) minus at most
    // 0.001 x the floor's diagonal per step for 1024 steps
    EXPECT_GE(r.mean_reward, -1024 * 0.001 * 5 * std::sqrt(2.0)) << r.method;
    EXPECT_LE(r.mean_reward, 100.0) << r.method;
    EXPECT_GT(r.train_env_steps, 0) << r.method;
    ASSERT_TRUE(r.paper.has_value()) << r.method;
  }
  EXPECT_DOUBLE_EQ(rows[3].paper->success, 0.929);  // multitask, simple
  EXPECT_DOUBLE_EQ(rows[0].paper->success, 1.0);    // oracle
  // the tables
  WriteStudyTables(rows, o);
  for (const char* name : {"table.json", "table.csv", "table.md"}) {
    EXPECT_TRUE(fs::exists(o.out_dir / name)) << name;
  }
  const std::string csv = StudyTableCsv(rows);
  EXPECT_NE(csv.find("multitask,16,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",92.90,"), std::string::npos) << csv;
  const std::string md = StudyTableMarkdown(rows, o);
  EXPECT_NE(md.find("| maml |"), std::string::npos) << md;
  EXPECT_NE(md.find("58.9 %"), std::string::npos) << md;
  fs::remove_all(o.out_dir);
}

TEST(BoxWorldStudyTest, OraclePpoLearnsTheSimpleTask) {
  // a quarter of the default budget (65,536 env steps, about 10 s): the
  // random policy reaches the target in about a third of the episodes on
  // one world (docs/boxworld.md: 13 of 40); PPO's mean action reaches it
  // every time (measured: 16/16, return 99.97)
  StudyOptions o = Tiny("learn", {"oracle"});
  o.budget = 0.25;
  const std::vector<StudyRow> rows = RunBoxWorldStudy(o);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_GE(rows[0].success, 0.9);
  EXPECT_GE(rows[0].mean_reward, 90.0);
  fs::remove_all(o.out_dir);
}

TEST(BoxWorldStudyTest, ResumeSkipsFinishedMethods) {
  const StudyOptions first = Tiny("resume", {"oracle"});
  const std::vector<StudyRow> a = RunBoxWorldStudy(first);
  ASSERT_EQ(a.size(), 1u);
  const fs::path result = first.out_dir / "oracle" / "result.json";
  ASSERT_TRUE(fs::exists(result));
  const auto written = fs::last_write_time(result);
  // again, with a second method: the oracle is read back, the baseline runs
  StudyOptions second = first;
  second.methods = {"oracle", "baseline"};
  std::vector<std::pair<std::string, bool>> seen;
  StudyCallbacks callbacks;
  callbacks.on_row = [&](const StudyRow& row, bool reused) { seen.push_back({row.method, reused}); };
  bool oracle_trained_again = false;
  callbacks.on_progress = [&](const StudyProgress& p) {
    if (p.method == "oracle") oracle_trained_again = true;
  };
  const std::vector<StudyRow> b = RunBoxWorldStudy(second, callbacks);
  ASSERT_EQ(b.size(), 2u);
  EXPECT_FALSE(oracle_trained_again);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0], std::make_pair(std::string("oracle"), true));
  EXPECT_EQ(seen[1], std::make_pair(std::string("baseline"), false));
  EXPECT_EQ(fs::last_write_time(result), written);
  EXPECT_DOUBLE_EQ(b[0].mean_reward, a[0].mean_reward);
  fs::remove_all(first.out_dir);
}

TEST(BoxWorldStudyTest, InitFromNeedsAMatchingCheckpoint) {
  // the fine-tune's starting point (experiment.init_from) is checked when the run is created
  const StudyOptions o = Tiny("init", {"oracle"});
  RunBoxWorldStudy(o);
  const fs::path checkpoint = LatestCheckpoint(o.out_dir / "oracle");
  auto message = [](TrainConfig c) {
    try {
      Trainer::Create(c);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  TrainConfig c = StudyMethodConfig(o, "finetune");
  c.experiment.run_dir = (o.out_dir / "ft_missing").string();
  c.experiment.init_from = (o.out_dir / "nowhere").string();
  EXPECT_NE(message(c).find("is not a checkpoint directory (no learner.pt)"), std::string::npos)
      << message(c);
  c.experiment.run_dir = (o.out_dir / "ft_sizes").string();
  c.experiment.init_from = checkpoint.string();
  c.agent.as<agents::PpoConfig>().hidden_dim = 32;
  EXPECT_NE(message(c).find("experiment.init_from: cannot start from"), std::string::npos)
      << message(c);
  c.experiment.run_dir = (o.out_dir / "ft_ok").string();
  c.agent = StudyMethodConfig(o, "finetune").agent;
  EXPECT_EQ(message(c), "(accepted)");
  // a run directory stands for its newest intact checkpoint
  c.experiment.run_dir = (o.out_dir / "ft_run").string();
  c.experiment.init_from = (o.out_dir / "oracle").string();
  EXPECT_EQ(message(c), "(accepted)");
  // verified as resume and eval verify: one flipped bit of learner.pt, or no state.json, is a
  // damaged checkpoint (both used to be loaded)
  const fs::path flipped = o.out_dir / "flipped";
  fs::copy(checkpoint, flipped);
  {
    std::fstream learner(flipped / "learner.pt", std::ios::in | std::ios::out | std::ios::binary);
    learner.seekg(100);
    const char byte = static_cast<char>(learner.get());
    learner.seekp(100);
    learner.put(static_cast<char>(byte ^ 0x01));
  }
  c.experiment.run_dir = (o.out_dir / "ft_flipped").string();
  c.experiment.init_from = flipped.string();
  EXPECT_NE(message(c).find("is damaged: learner.pt"), std::string::npos) << message(c);
  const fs::path stateless = o.out_dir / "stateless";
  fs::copy(checkpoint, stateless);
  fs::remove(stateless / "state.json");
  c.experiment.run_dir = (o.out_dir / "ft_stateless").string();
  c.experiment.init_from = stateless.string();
  EXPECT_NE(message(c).find("is damaged: state.json is missing"), std::string::npos)
      << message(c);
  // a FIFO for learner.pt is refused, not opened (opening it waited for a writer forever)
  const fs::path piped = o.out_dir / "piped";
  fs::copy(checkpoint, piped);
  fs::remove(piped / "learner.pt");
  ASSERT_EQ(mkfifo((piped / "learner.pt").c_str(), 0644), 0);
  c.experiment.run_dir = (o.out_dir / "ft_piped").string();
  c.experiment.init_from = piped.string();
  EXPECT_NE(message(c).find("is damaged: learner.pt"), std::string::npos) << message(c);
  fs::remove_all(o.out_dir);
}

TEST(BoxWorldStudyTest, AStopRequestStopsBeforeTheEvaluationAndTheStudyResumes) {
  const StudyOptions o = Tiny("stop", {"oracle"});
  const std::vector<StudyRow> first = RunBoxWorldStudy(o);
  // the run is trained, its row not yet written: the study stops before the evaluation (it
  // used to evaluate, write the tables and exit 0 while a signal waited)
  const fs::path result = o.out_dir / "oracle" / "result.json";
  ASSERT_TRUE(fs::exists(result));
  fs::remove(result);
  StudyCallbacks stopping;
  stopping.stop_requested = [] { return true; };
  try {
    RunBoxWorldStudy(o, stopping);
    ADD_FAILURE() << "the study did not stop";
  } catch (const StudyStopped& e) {
    EXPECT_NE(std::string(e.what()).find("before the evaluate phase of 'oracle'"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(result));
  const std::vector<StudyRow> resumed = RunBoxWorldStudy(o);
  ASSERT_EQ(resumed.size(), 1u);
  EXPECT_DOUBLE_EQ(resumed[0].mean_reward, first[0].mean_reward);
  fs::remove_all(o.out_dir);
}

TEST(BoxWorldStudyTest, TheComplexTaskUsesThePapersLayoutUnlessTold) {
  StudyOptions o;
  auto options = [&] { return StudyEnvOptions(o); };
  EXPECT_EQ(options().at("agent_start"), "anywhere");  // simple
  EXPECT_EQ(options().at("box_start_gap").get<double>(), -1.0);
  o.task = "complex";
  EXPECT_EQ(options().at("agent_start"), "corner");
  EXPECT_EQ(options().at("box_start_gap").get<double>(), kPaperBoxStartGap);
  o.layout = "anywhere";
  EXPECT_EQ(options().at("agent_start"), "anywhere");
  EXPECT_EQ(StudyTableJson({}, o).at("layout"), "anywhere");
  o.layout = "";
  EXPECT_EQ(StudyTableJson({}, o).at("layout"), "paper");
  EXPECT_NE(StudyTableMarkdown({}, o).find("the paper's layout (agent in a corner"),
            std::string::npos);
  // every method's config and the test tasks carry it
  o.config_dir = SourceDir() / "configs";
  o.out_dir = Scratch("layout");
  for (const std::string& method : StudyMethods()) {
    EXPECT_EQ(StudyMethodConfig(o, method).env.options.at("agent_start"), "corner") << method;
  }
  EXPECT_EQ(StudyTestSection(o).options.at("agent_start"), "corner");
}

TEST(BoxWorldStudyTest, BadOptionsAreOneLineErrors) {
  auto message = [](const StudyOptions& o) {
    try {
      RunBoxWorldStudy(o);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  StudyOptions o = Tiny("bad", {"oracle"});
  o.task = "medium";
  EXPECT_EQ(message(o), "--task must be simple or complex, got 'medium'");
  o = Tiny("bad", {"oracle", "mamll"});
  EXPECT_EQ(message(o),
            "--methods: unknown method 'mamll' (did you mean 'maml'?); the methods are oracle, "
            "baseline, finetune, multitask, maml, pearl, rl2");
  o = Tiny("bad", {"oracle"});
  o.distribution = "wide";
  EXPECT_EQ(message(o), "--distribution must be narrow or broad, got 'wide'");
  o = Tiny("bad", {"oracle"});
  o.budget = -1;
  EXPECT_NE(message(o).find("--budget must be a factor in (0, 1000]"), std::string::npos);
  o = Tiny("bad", {"oracle"});
  o.layout = "random";
  EXPECT_EQ(message(o), "--layout must be paper or anywhere, got 'random'");
  o = Tiny("bad", {"oracle"});
  o.config_dir = "/nonexistent";
  EXPECT_NE(message(o).find("no config '/nonexistent/boxworld_oracle_simple.yaml'"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(o.out_dir));  // nothing created for a bad study
}

// The published numbers come from configs/published/boxworld_study.yaml, not
// from the library: another file changes them, a malformed entry is an error
// naming it, and without the file there is no comparison column.
TEST(BoxWorldStudyTest, PublishedNumbersAreReadFromTheConfigDirectory) {
  StudyOptions o;
  o.config_dir = SourceDir() / "configs";
  o.task = "complex";
  ASSERT_TRUE(PaperResult(o, "maml").has_value());
  EXPECT_DOUBLE_EQ(PaperResult(o, "maml")->mean_reward, 17.59);
  EXPECT_FALSE(PaperResult(o, "rl2").has_value());  // the paper did not run it
  o.config_dir = Scratch("published");
  EXPECT_FALSE(PaperResult(o, "maml").has_value());  // no file
  std::filesystem::create_directories(o.config_dir / "published");
  std::ofstream(PublishedResultsFile(o)) << "complex:\n  maml: {mean_reward: 1.5, success: 0.25}\n";
  ASSERT_TRUE(PaperResult(o, "maml").has_value());
  EXPECT_DOUBLE_EQ(PaperResult(o, "maml")->success, 0.25);
  std::ofstream(PublishedResultsFile(o)) << "complex:\n  maml: {mean_reward: high}\n";
  try {
    PaperResult(o, "maml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("complex.maml"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace manyworlds::experiments
