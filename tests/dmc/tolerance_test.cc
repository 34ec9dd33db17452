#include "manyworlds/dmc/tolerance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "manyworlds/core/error.h"
#include "tests/dmc/recording.h"

namespace manyworlds::dmc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(ToleranceTest, EverySigmoidIsOneInsideAndValueAtMarginOneMarginAway) {
  for (size_t i = 0; i < SigmoidNames().size(); ++i) {
    const Sigmoid sigmoid = ParseSigmoid(SigmoidNames()[i]);
    ASSERT_EQ(static_cast<size_t>(sigmoid), i);
    const ToleranceShape shape{.lower = -1.0, .upper = 2.0, .margin = 0.5, .sigmoid = sigmoid,
                               .value_at_margin = 0.3};
    Validate(shape);
    SCOPED_TRACE(SigmoidNames()[i]);
    for (const double x : {-1.0, 0.0, 2.0}) EXPECT_EQ(Tolerance(x, shape), 1.0);
    // one margin below the lower bound and above the upper: value_at_margin
    EXPECT_NEAR(Tolerance(-1.5, shape), 0.3, 1e-12);
    EXPECT_NEAR(Tolerance(2.5, shape), 0.3, 1e-12);
    // falls with the distance, never below 0
    double previous = 1.0;
    for (double x = 2.0; x < 8.0; x += 0.01) {
      const double value = Tolerance(x, shape);
      EXPECT_LE(value, previous + 1e-15) << x;
      EXPECT_GE(value, 0.0) << x;
      previous = value;
    }
  }
}

TEST(ToleranceTest, ClosedFormsOfTheSigmoids) {
  auto at = [](Sigmoid s, double d, double v) {
    return Tolerance(d, {.lower = 0.0, .upper = 0.0, .margin = 1.0, .sigmoid = s,
                         .value_at_margin = v});
  };
  // gaussian: v^(d^2)
  EXPECT_NEAR(at(Sigmoid::kGaussian, 2.0, 0.1), std::pow(0.1, 4.0), 1e-15);
  EXPECT_NEAR(at(Sigmoid::kGaussian, 0.5, 0.1), std::pow(0.1, 0.25), 1e-15);
  // long tail: 1 / (d^2 (1/v - 1) + 1); reciprocal: 1 / (d (1/v - 1) + 1)
  EXPECT_NEAR(at(Sigmoid::kLongTail, 3.0, 0.5), 1.0 / 10.0, 1e-15);
  EXPECT_NEAR(at(Sigmoid::kReciprocal, 3.0, 0.5), 1.0 / 4.0, 1e-15);
  // linear and quadratic reach 0 at d = 1 / (1 - v) and 1 / sqrt(1 - v), and stay there
  EXPECT_NEAR(at(Sigmoid::kLinear, 1.5, 0.5), 0.25, 1e-15);
  EXPECT_EQ(at(Sigmoid::kLinear, 2.0, 0.5), 0.0);
  EXPECT_EQ(at(Sigmoid::kLinear, 50.0, 0.5), 0.0);
  EXPECT_NEAR(at(Sigmoid::kQuadratic, 1.0, 0.0), 0.0, 1e-15);
  EXPECT_EQ(at(Sigmoid::kCosine, 1.0, 0.0), 0.0);
  EXPECT_NEAR(at(Sigmoid::kCosine, 0.5, 0.0), 0.5, 1e-15);
  // hyperbolic and tanh_squared: 1/cosh and 1 - tanh^2 are the same curve, sech(dk)^(1 or 2)
  const double sech = at(Sigmoid::kHyperbolic, 2.0, 0.4);
  EXPECT_NEAR(sech, 1.0 / std::cosh(2.0 * std::acosh(2.5)), 1e-15);
  const double k = std::atanh(std::sqrt(0.6));
  EXPECT_NEAR(at(Sigmoid::kTanhSquared, 2.0, 0.4), 1.0 / std::pow(std::cosh(2.0 * k), 2), 1e-15);
}

TEST(ToleranceTest, MarginZeroIsTheIndicator) {
  const ToleranceShape spin{.lower = -kInf, .upper = -15.0, .margin = 0.0};
  EXPECT_EQ(Tolerance(-15.0, spin), 1.0);
  EXPECT_EQ(Tolerance(-20.0, spin), 1.0);
  EXPECT_EQ(Tolerance(-14.999, spin), 0.0);
}

// The shapes the three tasks build, in the closed forms the reference note derives
// (docs/reference/dmc_hipbmdp.md, 2.2): cheetah-run's speed term is clip(vx / 10, 0, 1) and
// walker-walk's move term clip(vx, 0, 1).
TEST(ToleranceTest, TheTasksLinearShapesAreClippedRamps) {
  const ToleranceShape run{.lower = 10.0, .upper = kInf, .margin = 10.0,
                           .sigmoid = Sigmoid::kLinear, .value_at_margin = 0.0};
  const ToleranceShape move{.lower = 1.0, .upper = kInf, .margin = 0.5,
                            .sigmoid = Sigmoid::kLinear, .value_at_margin = 0.5};
  for (double vx = -3.0; vx <= 15.0; vx += 0.125) {
    EXPECT_NEAR(Tolerance(vx, run), std::clamp(vx / 10.0, 0.0, 1.0), 1e-12) << vx;
    EXPECT_NEAR(Tolerance(vx, move), std::clamp(vx, 0.0, 1.0), 1e-12) << vx;
  }
}

// Against dm_control itself: its `tolerance` recorded on 140 shapes (8 sigmoids, bands,
// one-sided bounds, point targets, margin 0; values at the margin 0 to 0.9) at 47 points by
// scripts/record_dmc_tolerance.py (dm-control 1.0.50 from PyPI).
TEST(ToleranceTest, EqualsDmControlsOwnFunction) {
  const nlohmann::json recording = LoadRecording("tolerance_dm_control.json");
  ASSERT_TRUE(recording.contains("x"));
  const std::vector<double> xs = recording["x"].get<std::vector<double>>();
  auto bound = [](const nlohmann::json& b) {
    if (b.is_string()) return b.get<std::string>() == "inf" ? kInf : -kInf;
    return b.get<double>();
  };
  size_t compared = 0;
  for (const nlohmann::json& c : recording["cases"]) {
    const ToleranceShape shape{.lower = bound(c["lower"]), .upper = bound(c["upper"]),
                               .margin = c["margin"].get<double>(),
                               .sigmoid = ParseSigmoid(c["sigmoid"].get<std::string>()),
                               .value_at_margin = c["value_at_margin"].get<double>()};
    Validate(shape);
    const std::vector<double> values = c["value"].get<std::vector<double>>();
    ASSERT_EQ(values.size(), xs.size());
    for (size_t i = 0; i < xs.size(); ++i, ++compared) {
      EXPECT_NEAR(Tolerance(xs[i], shape), values[i], 1e-12)
          << c["sigmoid"] << " [" << shape.lower << ", " << shape.upper << "] margin "
          << shape.margin << " v " << shape.value_at_margin << " at x = " << xs[i];
    }
  }
  EXPECT_EQ(recording["cases"].size(), 140u);
  EXPECT_EQ(compared, 140u * xs.size());
  EXPECT_EQ(xs.size(), 47u);
}

TEST(ToleranceTest, BadShapesAreConfigErrorsNamingTheField) {
  EXPECT_THROW(Validate({.lower = 2.0, .upper = 1.0}), ConfigError);
  EXPECT_THROW(Validate({.margin = -1.0}), ConfigError);
  EXPECT_THROW(Validate({.margin = kInf}), ConfigError);
  // 0 at the margin: allowed for the sigmoids that reach 0, not for the others
  EXPECT_NO_THROW(Validate({.margin = 1.0, .sigmoid = Sigmoid::kLinear, .value_at_margin = 0.0}));
  try {
    Validate({.margin = 1.0, .sigmoid = Sigmoid::kGaussian, .value_at_margin = 0.0});
    ADD_FAILURE();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("gaussian sigmoid must be in (0, 1)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(Validate({.margin = 1.0, .value_at_margin = 1.0}), ConfigError);
  try {
    ParseSigmoid("gausian");
    ADD_FAILURE();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'gaussian'"), std::string::npos);
  }
}

}  // namespace
}  // namespace manyworlds::dmc
