// Trust region policy optimisation (Schulman et al. 2015) on the shared
// policy-gradient base, as garage's TRPO with its ConjugateGradientOptimizer:
//  1. g = gradient of the surrogate L(theta) = mean(r A) (+ c H), r = pi / pi_old;
//  2. s = H^-1 g by cg_iters conjugate-gradient iterations, where H v is the
//     Hessian of the mean KL(pi_old || pi_theta) times v (Fisher-vector
//     product by double backward through the flat parameters) + cg_damping v;
//  3. full step beta s with beta = sqrt(2 max_kl / s^T H s);
//  4. backtracking: try theta + ratio^k beta s for k = 0..max_backtracks-1;
//     accept the first step with mean KL <= max_kl that improves the
//     surrogate; if none does, keep theta (the step is rejected).
// The value network (MLP baseline) is then fitted for vf_epochs passes of
// vf_minibatch_size minibatches with Adam (garage's torch TRPO default).
// MT-TRPO is this with several tasks and architecture "mlp".
#ifndef MANYWORLDS_AGENTS_TRPO_TRPO_H_
#define MANYWORLDS_AGENTS_TRPO_TRPO_H_

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "manyworlds/agents/policy_gradient/policy_gradient.h"
#include "manyworlds/agents/trpo/trpo_config.h"

namespace manyworlds::agents {

// Solves A x = b for a symmetric positive-definite A given as a product
// function, by `iterations` conjugate-gradient steps from x = 0 (stops early
// when the residual's squared norm falls below 1e-10).
torch::Tensor ConjugateGradient(const std::function<torch::Tensor(const torch::Tensor&)>& product,
                                const torch::Tensor& b, int64_t iterations);

// Gradients of `params` as one vector; a parameter the output does not
// depend on (undefined gradient) contributes zeros.
torch::Tensor FlatGradient(const std::vector<torch::Tensor>& grads,
                           at::ArrayRef<torch::Tensor> params);

struct TrustRegionOptions {
  double max_kl = 0.01;
  int64_t cg_iters = 10;
  double backtrack_ratio = 0.8;
  int64_t max_backtracks = 15;
};

struct TrustRegionResult {
  bool accepted = false;
  double kl = 0.0;               // mean KL of the accepted step (0 if none)
  double surrogate_after = 0.0;  // surrogate of the accepted step
  int64_t backtracks = 0;        // fractions rejected before the accepted one
  // step_accepted, backtracks, kl and (if accepted) surrogate_after.
  void WriteTo(Metrics& metrics) const;
};

// TRPO's step, shared by TrpoLearner and MAML-TRPO: x solves F x = gradient
// by conjugate gradient (fisher gives F v), the full step is x scaled to the
// KL boundary (x^T F x = 2 max_kl), and fractions 1, r, r^2, ... of it (at
// most max_backtracks) are tried from `before` with set_params until
// evaluate() = (surrogate, mean KL) has KL <= max_kl and a surrogate above
// surrogate_before; if none qualifies, `before` is restored.
TrustRegionResult TrustRegionStep(const torch::Tensor& gradient,
                                  const std::function<torch::Tensor(const torch::Tensor&)>& fisher,
                                  const torch::Tensor& before,
                                  const std::function<void(const torch::Tensor&)>& set_params,
                                  const std::function<std::pair<double, double>()>& evaluate,
                                  double surrogate_before, const TrustRegionOptions& options);

class TrpoLearner : public PolicyGradientLearner {
 public:
  TrpoLearner(const TrpoConfig& config, const PolicySpaces& spaces);
  const TrpoConfig& config() const { return trpo_; }

 protected:
  const char* algo_name() const override { return "trpo"; }
  Metrics OptimizePolicy(const PolicySamples& samples) override;

 private:
  TrpoConfig trpo_;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_TRPO_TRPO_H_
