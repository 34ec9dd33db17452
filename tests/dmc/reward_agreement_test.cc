// Our finger-spin, cheetah-run and walker-walk rewards (dmc/rewards.h) against dm_control's
// own: tests/dmc/data/dmc_rewards.json holds, per step of random, sinusoid and set-state
// runs of dm_control 1.0.50 (scripts/record_dmc_rewards.py), the quantities each reward reads
// and dm_control's reward. Ours, fed those quantities, must give the same reward.
#include "manyworlds/dmc/rewards.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

namespace manyworlds::dmc {
namespace {

nlohmann::json LoadRecording() {
  const char* source = std::getenv("MANYWORLDS_SOURCE_DIR");
  EXPECT_NE(source, nullptr) << "MANYWORLDS_SOURCE_DIR is set by ctest";
  if (source == nullptr) return {};
  std::ifstream in(std::string(source) + "/tests/dmc/data/dmc_rewards.json");
  EXPECT_TRUE(in.good()) << "tests/dmc/data/dmc_rewards.json is missing";
  if (!in.good()) return {};
  return nlohmann::json::parse(in);
}

double OurReward(const std::string& task, const nlohmann::json& q) {
  if (task == "finger-spin") return FingerSpinReward(q.at("hinge_velocity").get<double>());
  if (task == "cheetah-run") return CheetahRunReward(q.at("com_velocity_x").get<double>());
  return WalkerWalkReward(q.at("torso_height").get<double>(), q.at("torso_upright").get<double>(),
                          q.at("com_velocity_x").get<double>());
}

TEST(DmcRewardAgreementTest, OurRewardsEqualDmControlsOnItsRecordedQuantities) {
  const nlohmann::json recording = LoadRecording();
  ASSERT_TRUE(recording.contains("tasks"));
  for (const std::string task : {"finger-spin", "cheetah-run", "walker-walk"}) {
    SCOPED_TRACE(task);
    ASSERT_TRUE(recording["tasks"].contains(task));
    double max_relative = 0.0, max_absolute = 0.0;
    int steps = 0, rewarded = 0, full = 0;
    for (const nlohmann::json& run : recording["tasks"][task]) {
      int t = 0;
      for (const nlohmann::json& step : run["steps"]) {
        const double theirs = step.at("reward").get<double>();
        const double ours = OurReward(task, step);
        const double error = std::abs(ours - theirs);
        // 1e-5 relative, or 1e-6 absolute near zero
        ASSERT_LE(error, std::max(1e-6, 1e-5 * std::abs(theirs)))
            << run["policy"].get<std::string>() << " step " << t << ": ours " << ours
            << ", dm_control " << theirs;
        max_absolute = std::max(max_absolute, error);
        if (theirs != 0.0) max_relative = std::max(max_relative, error / std::abs(theirs));
        rewarded += theirs > 0.0;
        full += theirs > 0.99;
        ++steps;
        ++t;
      }
    }
    // The recording reaches both ends of the reward, not only zeros.
    EXPECT_GE(steps, 600);
    EXPECT_GE(rewarded, 20);
    EXPECT_GE(full, 1);
    RecordProperty(task + "_max_relative_error", std::to_string(max_relative));
    std::printf("%s: %d steps, max relative error %.3g, max absolute error %.3g\n", task.c_str(),
                steps, max_relative, max_absolute);
  }
}

}  // namespace
}  // namespace manyworlds::dmc
