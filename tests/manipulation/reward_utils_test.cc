#include "manyworlds/manipulation/reward_utils.h"

#include <cmath>

#include <gtest/gtest.h>

namespace manyworlds::manipulation {
namespace {

constexpr double kTol = 1e-12;

TEST(LongTailToleranceTest, MatchesHandComputedValues) {
  EXPECT_EQ(LongTailTolerance(0.03, 0.0, 0.05, 0.1), 1.0);   // inside
  EXPECT_EQ(LongTailTolerance(0.05, 0.0, 0.05, 0.1), 1.0);   // on the bound
  EXPECT_NEAR(LongTailTolerance(0.15, 0.0, 0.05, 0.1), 0.1, kTol);  // d = 1
  // d = 0.5: 1 / (9 * 0.25 + 1) = 1 / 3.25
  EXPECT_NEAR(LongTailTolerance(0.10, 0.0, 0.05, 0.1), 1.0 / 3.25, kTol);
  EXPECT_NEAR(LongTailTolerance(0.0, 0.02, 0.05, 0.04), 1.0 / 3.25, kTol);  // below low
  // d = 2: 1 / 37
  EXPECT_NEAR(LongTailTolerance(0.25, 0.0, 0.05, 0.1), 1.0 / 37.0, kTol);
  EXPECT_EQ(LongTailTolerance(0.06, 0.0, 0.05, 0.0), 0.0);  // no margin
}

TEST(GaussianToleranceTest, MatchesHandComputedValues) {
  EXPECT_EQ(GaussianTolerance(0.03, 0.0, 0.05, 0.1), 1.0);              // inside
  EXPECT_NEAR(GaussianTolerance(0.15, 0.0, 0.05, 0.1), 0.1, kTol);      // d = 1
  EXPECT_NEAR(GaussianTolerance(0.10, 0.0, 0.05, 0.1), std::pow(0.1, 0.25), kTol);  // d = 0.5
  EXPECT_NEAR(GaussianTolerance(0.0, 0.02, 0.05, 0.04), std::pow(0.1, 0.25), kTol);  // below low
  EXPECT_NEAR(GaussianTolerance(0.25, 0.0, 0.05, 0.1), 1e-4, kTol);     // d = 2: 0.1^4
  EXPECT_EQ(GaussianTolerance(0.06, 0.0, 0.05, 0.0), 0.0);              // no margin
}

TEST(HamacherProductTest, MatchesHandComputedValues) {
  EXPECT_NEAR(HamacherProduct(0.5, 0.5), 1.0 / 3.0, kTol);
  EXPECT_NEAR(HamacherProduct(0.2, 0.6), 0.12 / 0.68, kTol);
  EXPECT_NEAR(HamacherProduct(1.0, 0.37), 0.37, kTol);
  EXPECT_EQ(HamacherProduct(0.0, 0.0), 0.0);
  EXPECT_EQ(HamacherProduct(0.0, 0.8), 0.0);
}

CagingInputs Caged(double gripper_action) {
  // Pads 2.5 cm either side of the object, tcp on it: fully caged.
  CagingInputs in;
  in.obj = in.obj_init = {0.0, 0.6, 0.02};
  in.left_pad = {0.0, 0.575, 0.02};
  in.right_pad = {0.0, 0.625, 0.02};
  in.tcp = {0.0, 0.6, 0.02};
  in.tcp_init = {0.0, 0.6, 0.12};
  in.gripper_action = gripper_action;
  return in;
}

TEST(GripperCagingRewardTest, FullyCaged) {
  CagingParams high;
  high.high_density = true;
  EXPECT_NEAR(GripperCagingReward(Caged(1.0), high), 1.0, kTol);
  // gripping 0.5: H(1, 0.5) = 0.5, (0.5 + 1) / 2
  EXPECT_NEAR(GripperCagingReward(Caged(0.5), high), 0.75, kTol);
  EXPECT_NEAR(GripperCagingReward(Caged(-1.0), high), 0.5, kTol);
  CagingParams plain;
  EXPECT_NEAR(GripperCagingReward(Caged(1.0), plain), 1.0, kTol);
  EXPECT_NEAR(GripperCagingReward(Caged(0.0), plain), 0.0, kTol);
}

TEST(GripperCagingRewardTest, AtTheMargins) {
  // Pads 10 cm from the object: margin |0.1 - 0.05| = 0.05, d = 1, each 0.1,
  // caging_y = H(0.1, 0.1) = 1/19. tcp 10 cm above: margin 0.095, d = 1,
  // caging_xz = 0.1. caging = H(1/19, 1/10) = 1/28; gripping 0.
  CagingInputs in = Caged(1.0);
  in.left_pad = {0.0, 0.5, 0.12};
  in.right_pad = {0.0, 0.7, 0.12};
  in.tcp = {0.0, 0.6, 0.12};
  CagingParams high;
  high.high_density = true;
  EXPECT_NEAR(GripperCagingReward(in, high), 1.0 / 56.0, kTol);
  // Medium density: reach = tol(0.1, (0, 0.01), margin 0.09) = 0.1.
  CagingParams medium;
  medium.medium_density = true;
  EXPECT_NEAR(GripperCagingReward(in, medium), 0.05, kTol);
}

TEST(RectPrismToleranceTest, ScalesInsideAndIsOneOutside) {
  const Vec3 zero{0, 0, 0}, one{1, 2, -4};  // corners in any order of signs
  EXPECT_NEAR(RectPrismTolerance({0.5, 1.0, -2.0}, zero, one), 0.125, kTol);
  EXPECT_NEAR(RectPrismTolerance({1, 2, -4}, zero, one), 1.0, kTol);
  EXPECT_NEAR(RectPrismTolerance({0, 1, -1}, zero, one), 0.0, kTol);  // a face of the zero corner
  EXPECT_EQ(RectPrismTolerance({0.5, 1.0, 0.1}, zero, one), 1.0);     // outside in z
  EXPECT_EQ(RectPrismTolerance({-0.1, 1.0, -2.0}, zero, one), 1.0);
}

TEST(DistanceTest, Euclidean) {
  EXPECT_NEAR(Distance({0, 0, 0}, {1, 2, 2}), 3.0, kTol);
}

}  // namespace
}  // namespace manyworlds::manipulation
