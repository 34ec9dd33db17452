// The time left that the progress lines print (apps/manyworlds/remaining_time.h).
#include "apps/manyworlds/remaining_time.h"

#include <chrono>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace manyworlds::cli {
namespace {

using Clock = RemainingTime::Clock;
using std::chrono::milliseconds;
using std::chrono::seconds;

TEST(FormatDurationTest, HoursMinutesSeconds) {
  EXPECT_EQ(FormatDuration(0), "0s");
  EXPECT_EQ(FormatDuration(7.4), "7s");
  EXPECT_EQ(FormatDuration(249), "4m09s");
  EXPECT_EQ(FormatDuration(3900), "1h05m");
  EXPECT_EQ(FormatDuration(-1), "?");
  EXPECT_EQ(FormatDuration(std::numeric_limits<double>::quiet_NaN()), "?");
  EXPECT_EQ(FormatDuration(1e9), "?");
}

TEST(RemainingTimeTest, UnknownUntilSomethingIsDone) {
  RemainingTime eta;
  const Clock::time_point t0{};
  EXPECT_LT(eta.Update(0, 100, t0), 0);
  EXPECT_LT(eta.Update(0, 100, t0 + seconds(5)), 0);  // no progress, no rate
  EXPECT_NEAR(eta.Update(10, 100, t0 + seconds(10)), 90.0, 1e-9);  // 1 per second
}

// A training run: 1,500 warm-up steps in 10 s, then 7 steps per second. After
// a minute at the slow rate the estimate is the slow rate's, where a rate since
// the start would still promise the end far too early.
TEST(RemainingTimeTest, FollowsTheRateOfTheLastWindowNotSinceTheStart) {
  RemainingTime eta(seconds(60));
  const Clock::time_point t0{};
  const double total = 100000;
  eta.Update(0, total, t0);
  eta.Update(1500, total, t0 + seconds(10));
  double steps = 1500, left = -1;
  for (int ms = 100; ms <= 300000; ms += 100) {  // five minutes, ten calls a second
    steps += 0.7;
    left = eta.Update(steps, total, t0 + seconds(10) + milliseconds(ms));
  }
  const double truth = (total - steps) / 7.0;  // a rate since the start says 0.6 of it
  EXPECT_NEAR(left, truth, 0.01 * truth);
}

TEST(RemainingTimeTest, UntilTheWindowFillsTheRateIsSinceTheFirstUpdate) {
  RemainingTime eta(seconds(60));
  const Clock::time_point t0{};
  eta.Update(0, 1000, t0);
  EXPECT_NEAR(eta.Update(100, 1000, t0 + milliseconds(500)), 4.5, 1e-9);  // 200/s
  EXPECT_NEAR(eta.Update(200, 1000, t0 + seconds(10)), 40.0, 1e-9);       // 20/s since t0
}

TEST(RemainingTimeTest, ResetStartsOver) {
  RemainingTime eta;
  const Clock::time_point t0{};
  eta.Update(0, 100, t0);
  EXPECT_GT(eta.Update(50, 100, t0 + seconds(50)), 0);
  eta.Reset();
  EXPECT_LT(eta.Update(60, 100, t0 + seconds(51)), 0);
  EXPECT_NEAR(eta.Update(70, 100, t0 + seconds(52)), 3.0, 1e-9);  // 10 per second
}

TEST(RemainingTimeTest, DoneMeansNothingLeft) {
  RemainingTime eta;
  const Clock::time_point t0{};
  eta.Update(0, 10, t0);
  EXPECT_EQ(eta.Update(10, 10, t0 + seconds(1)), 0);
  EXPECT_EQ(eta.Update(12, 10, t0 + seconds(2)), 0);  // overshoot is not negative time
}

}  // namespace
}  // namespace manyworlds::cli
