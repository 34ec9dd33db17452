// garage's LinearFeatureBaseline: a value estimate linear in the features
//   [clip(x, -10, 10), clip(x, -10, 10)^2, t/100, (t/100)^2, (t/100)^3, 1]
// of the (task-conditioned) observation x and the step t within the episode,
// fitted by regularised least squares (reg 1e-5, multiplied by 10 up to 5
// times while the solution is not finite), refitted every iteration to the
// discounted returns.
#ifndef MANYWORLDS_RL_LINEAR_BASELINE_H_
#define MANYWORLDS_RL_LINEAR_BASELINE_H_

#include <cstdint>

#include <torch/torch.h>

namespace manyworlds::rl {

class LinearFeatureBaseline {
 public:
  explicit LinearFeatureBaseline(int64_t input_dim, double reg_coeff = 1e-5);

  // x (B, input_dim), t (B) steps into the episode -> (B, 2 * input_dim + 4).
  torch::Tensor Features(const torch::Tensor& x, const torch::Tensor& t) const;
  // Least squares of returns (B) on the features; before the first fit the
  // prediction is 0 (garage's).
  void Fit(const torch::Tensor& x, const torch::Tensor& t, const torch::Tensor& returns);
  torch::Tensor Predict(const torch::Tensor& x, const torch::Tensor& t) const;

  const torch::Tensor& coefficients() const { return coefficients_; }
  void set_coefficients(const torch::Tensor& c);

 private:
  int64_t input_dim_;
  double reg_coeff_;
  torch::Tensor coefficients_;  // (2 * input_dim + 4) float64, zeros before a fit
};

}  // namespace manyworlds::rl

#endif  // MANYWORLDS_RL_LINEAR_BASELINE_H_
