#include "manyworlds/core/policy.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "tests/core/toy_env.h"

namespace manyworlds {
namespace {

using testing::ToyEnv;

// Always the same action; counts calls.
class ConstantPolicy : public Policy {
 public:
  explicit ConstantPolicy(float value) : value_(value) {}
  void BeginEpisode() override { ++episodes_; }
  void Act(std::span<const float>, std::span<const float>, std::span<float> action) override {
    ++acts_;
    std::fill(action.begin(), action.end(), value_);
  }
  int episodes_ = 0;
  int64_t acts_ = 0;

 private:
  float value_;
};

// A ToyEnv without a time limit and without the "success" field.
class EndlessToy : public ToyEnv {
 public:
  EndlessToy() : ToyEnv(false, 0) { mutable_spec().info_fields = {"progress", "distance"}; }
};

TEST(RolloutTest, TruncatedEpisodesHaveTheLimitLengthAndNoSuccess) {
  ToyEnv env(false, 7);
  env.SetTaskState(TaskState{"toy", {{"target", 0.9}}});
  ConstantPolicy stay(0.0f);
  const RolloutSummary summary = Rollout(env, stay, 3);
  ASSERT_EQ(summary.episodes.size(), 3u);
  EXPECT_EQ(stay.episodes_, 3);
  EXPECT_EQ(stay.acts_, 21);
  double total = 0.0;
  for (const auto& e : summary.episodes) {
    EXPECT_EQ(e.length, 7);
    EXPECT_TRUE(e.truncated);
    EXPECT_FALSE(e.terminated);
    EXPECT_EQ(e.success, 0);
    EXPECT_LT(e.episode_return, -4.0);  // about -0.9 per step
    total += e.episode_return;
  }
  EXPECT_DOUBLE_EQ(summary.mean_return, total / 3);
  EXPECT_DOUBLE_EQ(summary.mean_length, 7.0);
  EXPECT_DOUBLE_EQ(summary.success_rate, 0.0);
}

TEST(RolloutTest, ReachingTheTargetTerminatesWithSuccess) {
  ToyEnv env(false, 1000);
  env.SetTaskState(TaskState{"toy", {{"target", 0.5}}});
  ConstantPolicy right(1.0f);
  const RolloutSummary summary = Rollout(env, right, 2);
  for (const auto& e : summary.episodes) {
    EXPECT_TRUE(e.terminated);
    EXPECT_EQ(e.success, 1);
    EXPECT_GT(e.length, 2);
    EXPECT_LT(e.length, 10);
  }
  EXPECT_DOUBLE_EQ(summary.success_rate, 1.0);
}

TEST(RolloutTest, EpisodesWithoutALimitAreCutAndSuccessIsUnknown) {
  EndlessToy env;
  env.SetTaskState(TaskState{"toy", {{"target", 0.9}}});
  ConstantPolicy left(-1.0f);
  const RolloutSummary summary = Rollout(env, left, 2, 25);
  for (const auto& e : summary.episodes) {
    EXPECT_EQ(e.length, 25);
    EXPECT_TRUE(e.truncated);
    EXPECT_EQ(e.success, -1);
  }
  EXPECT_LT(summary.success_rate, 0.0);
  const nlohmann::json json = summary.ToJson();
  EXPECT_TRUE(json["success_rate"].is_null());
  EXPECT_TRUE(json["episodes"][0]["success"].is_null());
}

TEST(RolloutTest, RandomPolicyRolloutsAreDeterministic) {
  auto run = [] {
    ToyEnv env(true, 30);
    env.Seed(4);
    env.SeedTask(5);
    RandomPolicy policy(env.spec().action_space, 6);
    return Rollout(env, policy, 4).ToJson().dump();
  };
  EXPECT_EQ(run(), run());
}

TEST(RolloutTest, RejectsBadArguments) {
  ToyEnv env;
  ConstantPolicy stay(0.0f);
  EXPECT_THROW(Rollout(env, stay, -1), ConfigError);
  EXPECT_THROW(Rollout(env, stay, 1, 0), ConfigError);
  const RolloutSummary none = Rollout(env, stay, 0);
  EXPECT_TRUE(none.episodes.empty());
  EXPECT_EQ(none.mean_return, 0.0);
}

TEST(RolloutSummaryTest, JsonHasTheDocumentedShapeAndStableText) {
  RolloutSummary summary;
  summary.episodes.push_back({-1.5, 10, 1, true, false});
  summary.episodes.push_back({0.25, 4, 0, false, true});
  summary.mean_return = -0.625;
  summary.mean_length = 7.0;
  summary.success_rate = 0.5;
  EXPECT_EQ(summary.ToJson().dump(),
            R"({"episodes":[{"length":10,"return":-1.5,"success":1},)"
            R"({"length":4,"return":0.25,"success":0}],"mean_return":-0.625,)"
            R"("success_rate":0.5})");
  summary.success_rate = -1.0;
  summary.episodes = {{0.1, 3, -1, false, true}};
  summary.mean_return = 0.1;
  EXPECT_EQ(summary.ToJson().dump(),
            R"({"episodes":[{"length":3,"return":0.1,"success":null}],"mean_return":0.1,)"
            R"("success_rate":null})");
}

}  // namespace
}  // namespace manyworlds
