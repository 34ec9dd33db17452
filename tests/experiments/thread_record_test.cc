// A run resumes only with the thread counts its checkpoint was written
// with (a product's rounding depends on them); its own binary because
// nn::SetThreads is process-wide.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "manyworlds/agents/sac/sac_config.h"
#include "manyworlds/core/error.h"
#include "manyworlds/experiments/trainer.h"
#include "manyworlds/nn/threads.h"

namespace manyworlds::experiments {
namespace {

namespace fs = std::filesystem;

TEST(ThreadRecordTest, ResumeRefusesOtherBlasThreadCounts) {
  const fs::path dir =
      fs::temp_directory_path() / ("mw_thread_record_test_" + std::to_string(getpid()));
  fs::remove_all(dir);
  TrainConfig c;
  c.env.id = "point-nav";
  c.env.num_tasks = 2;
  c.env.options = {{"horizon", 50}};
  c.agent.as<agents::SacConfig>().hidden_dim = 16;
  c.agent.as<agents::SacConfig>().num_layers = 1;
  c.agent.as<agents::SacConfig>().batch_size = 16;
  c.experiment.steps_per_task = 200;
  c.experiment.warmup_steps = 50;
  c.experiment.eval_every = 100;
  c.experiment.eval_episodes = 1;
  c.experiment.checkpoint_every = 100;
  c.experiment.run_dir = dir.string();
  {
    Trainer t = Trainer::Create(c);
    TrainCallbacks stop;
    stop.stop_after_step = 100;
    ASSERT_FALSE(t.Run(stop).finished);
  }
  const int blas = nn::CurrentThreads().blas_threads;
  if (blas < 1) GTEST_SKIP() << "the BLAS library is not OpenBLAS";
  const fs::path checkpoint = LatestCheckpoint(dir);
  EXPECT_FALSE(EvaluationThreadWarning(checkpoint).has_value());
  nn::SetThreads(1, blas == 1 ? 2 : 1);
  // eval warns (and still evaluates); resume refuses
  const auto warning = EvaluationThreadWarning(checkpoint);
  ASSERT_TRUE(warning.has_value());
  EXPECT_NE(warning->find("OPENBLAS_NUM_THREADS=" + std::to_string(blas) + " reproduces them"),
            std::string::npos)
      << *warning;
  EXPECT_FALSE(EvaluationThreadWarning(dir / "no_such_checkpoint").has_value());
  try {
    Trainer::Resume(dir);
    ADD_FAILURE() << "resumed with another BLAS thread count";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("OPENBLAS_NUM_THREADS=" + std::to_string(blas)),
              std::string::npos)
        << e.what();
  }
  nn::SetThreads(1, blas);
  Trainer again = Trainer::Resume(dir);
  EXPECT_EQ(again.step(), 100);
  EXPECT_TRUE(again.Run().finished);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace manyworlds::experiments
