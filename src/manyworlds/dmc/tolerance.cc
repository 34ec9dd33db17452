#include "manyworlds/dmc/tolerance.h"

#include <cmath>
#include <numbers>

#include "manyworlds/core/error.h"
#include "manyworlds/core/registry.h"

namespace manyworlds::dmc {
namespace {

bool AllowsZeroAtMargin(Sigmoid s) {
  return s == Sigmoid::kCosine || s == Sigmoid::kLinear || s == Sigmoid::kQuadratic;
}

// s(d): 1 at d = 0, v at d = 1 (the table in tolerance.h).
double SigmoidAt(double d, double v, Sigmoid sigmoid) {
  const double pi = std::numbers::pi;
  switch (sigmoid) {
    case Sigmoid::kGaussian: {
      const double k = std::sqrt(-2.0 * std::log(v));
      return std::exp(-0.5 * (d * k) * (d * k));
    }
    case Sigmoid::kHyperbolic:
      return 1.0 / std::cosh(d * std::acosh(1.0 / v));
    case Sigmoid::kLongTail: {
      const double k = std::sqrt(1.0 / v - 1.0);
      return 1.0 / ((d * k) * (d * k) + 1.0);
    }
    case Sigmoid::kReciprocal:
      return 1.0 / (std::abs(d) * (1.0 / v - 1.0) + 1.0);
    case Sigmoid::kCosine: {
      const double scaled = d * std::acos(2.0 * v - 1.0) / pi;
      return std::abs(scaled) < 1.0 ? (1.0 + std::cos(pi * scaled)) / 2.0 : 0.0;
    }
    case Sigmoid::kLinear: {
      const double scaled = d * (1.0 - v);
      return std::abs(scaled) < 1.0 ? 1.0 - scaled : 0.0;
    }
    case Sigmoid::kQuadratic: {
      const double scaled = d * std::sqrt(1.0 - v);
      return std::abs(scaled) < 1.0 ? 1.0 - scaled * scaled : 0.0;
    }
    case Sigmoid::kTanhSquared: {
      const double t = std::tanh(d * std::atanh(std::sqrt(1.0 - v)));
      return 1.0 - t * t;
    }
  }
  return 0.0;
}

}  // namespace

const std::vector<std::string>& SigmoidNames() {
  // in the order of the enum
  static const std::vector<std::string> names = {"gaussian", "hyperbolic", "long_tail",
                                                 "reciprocal", "cosine", "linear",
                                                 "quadratic", "tanh_squared"};
  return names;
}

Sigmoid ParseSigmoid(std::string_view name) {
  const std::vector<std::string>& names = SigmoidNames();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return static_cast<Sigmoid>(i);
  }
  std::string all;
  for (const std::string& n : names) all += (all.empty() ? "" : ", ") + n;
  throw ConfigError("unknown sigmoid '" + ShortenForMessage(std::string(name)) + "'" +
                    SuggestNearest(name, names) + "; allowed: " + all);
}

void Validate(const ToleranceShape& shape) {
  if (std::isnan(shape.lower) || std::isnan(shape.upper) || shape.lower > shape.upper) {
    throw ConfigError("tolerance: lower bound " + std::to_string(shape.lower) +
                      " must be <= upper bound " + std::to_string(shape.upper));
  }
  if (!(shape.margin >= 0.0) || !std::isfinite(shape.margin)) {
    throw ConfigError("tolerance: margin must be finite and >= 0, got " +
                      std::to_string(shape.margin));
  }
  if (shape.margin == 0.0) return;  // the indicator: value_at_margin is not used (as in dm_control)
  const double v = shape.value_at_margin;
  const bool zero_ok = AllowsZeroAtMargin(shape.sigmoid);
  if (!(v < 1.0) || !(zero_ok ? v >= 0.0 : v > 0.0)) {
    throw ConfigError("tolerance: value_at_margin of the " +
                      SigmoidNames()[static_cast<size_t>(shape.sigmoid)] + " sigmoid must be in " +
                      (zero_ok ? "[0, 1)" : "(0, 1)") + ", got " + std::to_string(v));
  }
}

double Tolerance(double x, const ToleranceShape& shape) {
  if (shape.lower <= x && x <= shape.upper) return 1.0;
  if (shape.margin == 0.0) return 0.0;
  const double distance = x < shape.lower ? shape.lower - x : x - shape.upper;
  return SigmoidAt(distance / shape.margin, shape.value_at_margin, shape.sigmoid);
}

}  // namespace manyworlds::dmc
