#include "manyworlds/rl/linear_baseline.h"

#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds::rl {

LinearFeatureBaseline::LinearFeatureBaseline(int64_t input_dim, double reg_coeff)
    : input_dim_(input_dim), reg_coeff_(reg_coeff) {
  if (input_dim <= 0 || !(reg_coeff > 0)) {
    throw ConfigError("LinearFeatureBaseline: input_dim and reg_coeff must be > 0");
  }
  coefficients_ = torch::zeros({2 * input_dim + 4}, torch::kFloat64);
}

torch::Tensor LinearFeatureBaseline::Features(const torch::Tensor& x,
                                              const torch::Tensor& t) const {
  if (x.dim() != 2 || x.size(1) != input_dim_ || t.dim() != 1 || t.size(0) != x.size(0)) {
    throw Error("LinearFeatureBaseline: expected x (B, " + std::to_string(input_dim_) +
                ") and t (B)");
  }
  const torch::Tensor o = x.to(torch::kFloat64).clamp(-10.0, 10.0);
  const torch::Tensor s = (t.to(torch::kFloat64) / 100.0).unsqueeze(1);
  return torch::cat({o, o.square(), s, s.square(), s.pow(3), torch::ones_like(s)}, 1);
}

void LinearFeatureBaseline::Fit(const torch::Tensor& x, const torch::Tensor& t,
                                const torch::Tensor& returns) {
  const torch::Tensor f = Features(x, t);
  const torch::Tensor y = returns.to(torch::kFloat64).reshape({-1, 1});
  const torch::Tensor gram = f.t().mm(f);
  const torch::Tensor rhs = f.t().mm(y);
  const torch::Tensor eye = torch::eye(f.size(1), torch::kFloat64);
  double reg = reg_coeff_;
  for (int attempt = 0; attempt < 5; ++attempt) {
    const torch::Tensor solution = torch::linalg_solve(gram + reg * eye, rhs).squeeze(1);
    if (torch::isfinite(solution).all().item<bool>()) {
      coefficients_ = solution;
      return;
    }
    reg *= 10.0;
  }
}

torch::Tensor LinearFeatureBaseline::Predict(const torch::Tensor& x, const torch::Tensor& t) const {
  return Features(x, t).mv(coefficients_).to(torch::kFloat32);
}

void LinearFeatureBaseline::set_coefficients(const torch::Tensor& c) {
  if (c.numel() != coefficients_.numel()) {
    throw Error("LinearFeatureBaseline: expected " + std::to_string(coefficients_.numel()) +
                " coefficients, got " + std::to_string(c.numel()));
  }
  coefficients_ = c.to(torch::kFloat64).reshape({-1}).clone();
}

}  // namespace manyworlds::rl
