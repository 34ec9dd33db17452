// dm_control's reward shape: a soft indicator of "x lies in [lower, upper]" (its
// utils/rewards.py `tolerance`, the function every DeepMind-Control task builds its reward
// from). Written from its documented definition:
//
//   Tolerance(x, {.lower = 1.2, .upper = inf, .margin = 0.6})   // walker's "standing"
//
// is 1 inside the bounds; outside, with d the distance to the nearer bound divided by
// `margin`, it is sigmoid(d), a curve that is 1 at d = 0 and `value_at_margin` at d = 1. With
// margin 0 it is the plain indicator. Per sigmoid, s(d) at distance d (v = value_at_margin):
//
//   gaussian      exp(-(d k)^2 / 2),        k = sqrt(-2 ln v)
//   hyperbolic    1 / cosh(d k),            k = acosh(1 / v)
//   long_tail     1 / ((d k)^2 + 1),        k = sqrt(1 / v - 1)
//   reciprocal    1 / (|d| k + 1),          k = 1 / v - 1
//   cosine        (1 + cos(pi d k)) / 2 where |d k| < 1, else 0,   k = acos(2 v - 1) / pi
//   linear        1 - d k where |d k| < 1, else 0,                 k = 1 - v
//   quadratic     1 - (d k)^2 where |d k| < 1, else 0,             k = sqrt(1 - v)
//   tanh_squared  1 - tanh(d k)^2,          k = atanh(sqrt(1 - v))
//
// cosine, linear and quadratic accept v in [0, 1); the others need v in (0, 1).
#ifndef MANYWORLDS_DMC_TOLERANCE_H_
#define MANYWORLDS_DMC_TOLERANCE_H_

#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace manyworlds::dmc {

enum class Sigmoid {
  kGaussian,
  kHyperbolic,
  kLongTail,
  kReciprocal,
  kCosine,
  kLinear,
  kQuadratic,
  kTanhSquared
};

struct ToleranceShape {
  double lower = 0.0;  // inclusive bounds; either may be infinite
  double upper = 0.0;
  double margin = 0.0;  // >= 0; 0: the indicator of [lower, upper]
  Sigmoid sigmoid = Sigmoid::kGaussian;
  double value_at_margin = 0.1;  // dm_control's default
};

// Throws ConfigError naming the field for lower > upper, a negative or non-finite margin, or
// (with a margin) a value_at_margin outside the sigmoid's range.
void Validate(const ToleranceShape& shape);

// In [0, 1]; 1 inside the bounds. `shape` must be valid (Validate).
double Tolerance(double x, const ToleranceShape& shape);

// "gaussian", ... as dm_control names them; ParseSigmoid throws ConfigError listing them.
const std::vector<std::string>& SigmoidNames();
Sigmoid ParseSigmoid(std::string_view name);

}  // namespace manyworlds::dmc

#endif  // MANYWORLDS_DMC_TOLERANCE_H_
