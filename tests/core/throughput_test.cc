#include "manyworlds/core/throughput.h"

#include <memory>

#include <gtest/gtest.h>

#include "manyworlds/core/error.h"
#include "tests/core/toy_env.h"

namespace manyworlds {
namespace {

using ::manyworlds::testing::ToyEnv;

std::unique_ptr<Env> MakeToy(int i) { return std::make_unique<ToyEnv>(i % 2 == 1, 20); }

TEST(ThroughputTest, MeasuresEveryRepeat) {
  for (int threads : {1, 2}) {
    const ThroughputResult r = MeasureThroughput(
        MakeToy, {.num_envs = 5, .num_threads = threads, .steps = 2000, .repeats = 3, .seed = 1});
    ASSERT_EQ(r.samples.size(), 3u);
    for (double s : r.samples) EXPECT_GT(s, 0.0);
    EXPECT_GE(r.steps_per_s, r.min_steps_per_s);
    EXPECT_LE(r.steps_per_s, r.max_steps_per_s);
    EXPECT_NEAR(r.ns_per_step, 1e9 / r.steps_per_s, 1e-6 * r.ns_per_step);
    EXPECT_EQ(r.steps_per_repeat, 2000);  // 400 batches of 5
    EXPECT_EQ(r.num_envs, 5);
    EXPECT_EQ(r.num_threads, threads);
  }
}

TEST(ThroughputTest, RoundsStepsUpToWholeBatches) {
  const ThroughputResult r = MeasureThroughput(
      MakeToy, {.num_envs = 4, .num_threads = 1, .steps = 10, .repeats = 2, .seed = 0});
  EXPECT_EQ(r.steps_per_repeat, 12);
  EXPECT_EQ(r.samples.size(), 2u);
}

TEST(ThroughputTest, RejectsBadOptions) {
  const ThroughputOptions good{.num_envs = 2, .num_threads = 1, .steps = 10, .repeats = 1};
  ThroughputOptions o = good;
  o.num_envs = 0;
  EXPECT_THROW(MeasureThroughput(MakeToy, o), ConfigError);
  o = good;
  o.num_threads = 0;
  EXPECT_THROW(MeasureThroughput(MakeToy, o), ConfigError);
  o = good;
  o.steps = 0;
  EXPECT_THROW(MeasureThroughput(MakeToy, o), ConfigError);
  o = good;
  o.repeats = 0;
  EXPECT_THROW(MeasureThroughput(MakeToy, o), ConfigError);
  EXPECT_THROW(MeasureThroughput([](int) { return std::unique_ptr<Env>(); }, good), ConfigError);
}

}  // namespace
}  // namespace manyworlds
