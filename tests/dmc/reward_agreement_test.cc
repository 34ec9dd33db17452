// Our finger-spin, cheetah-run and walker-walk rewards (dmc/rewards.h) against dm_control's
// own: tests/dmc/data/dmc_rewards.json holds, per step of random, sinusoid, zero-action and
// set-state runs of dm_control 1.0.50 (scripts/record_dmc_rewards.py), the quantities each
// reward reads (the first 300 steps of an episode) and dm_control's reward. Ours, fed those
// quantities, must give the same reward.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "manyworlds/dmc/rewards.h"
#include "tests/dmc/recording.h"

namespace manyworlds::dmc {
namespace {

// `q` in the order of the recording's "names", which are rewards.h's arguments.
double OurReward(const std::string& task, const nlohmann::json& q) {
  if (task == "finger-spin") return FingerSpinReward(q.at(0).get<double>());
  if (task == "cheetah-run") return CheetahRunReward(q.at(0).get<double>());
  return WalkerWalkReward(q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>());
}

TEST(DmcRewardAgreementTest, OurRewardsEqualDmControlsOnItsRecordedQuantities) {
  const nlohmann::json recording = LoadRecording("dmc_rewards.json");
  ASSERT_TRUE(recording.contains("tasks"));
  for (const std::string task : {"finger-spin", "cheetah-run", "walker-walk"}) {
    SCOPED_TRACE(task);
    ASSERT_TRUE(recording["tasks"].contains(task));
    const nlohmann::json& record = recording["tasks"][task];
    const std::vector<std::string> names =
        task == "finger-spin" ? std::vector<std::string>{"hinge_velocity"}
        : task == "cheetah-run"
            ? std::vector<std::string>{"com_velocity_x"}
            : std::vector<std::string>{"torso_height", "torso_upright", "com_velocity_x"};
    ASSERT_EQ(record["names"].get<std::vector<std::string>>(), names);
    double max_relative = 0.0, max_absolute = 0.0;
    int steps = 0, rewarded = 0, full = 0;
    for (const nlohmann::json& run : record["runs"]) {
      const nlohmann::json& quantities = run["quantities"];
      ASSERT_LE(quantities.size(), run["rewards"].size());
      for (size_t t = 0; t < quantities.size(); ++t) {
        const double theirs = run["rewards"][t].get<double>();
        const double ours = OurReward(task, quantities[t]);
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
