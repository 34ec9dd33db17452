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

#include "manyworlds/agents/policy_gradient/policy_gradient.h"
#include "manyworlds/agents/trpo/trpo_config.h"

namespace manyworlds::agents {



// Solves A x = b for a symmetric positive-definite A given as a product
// function, by `iterations` conjugate-gradient steps from x = 0 (stops early
// when the residual's squared norm falls below 1e-10).
torch::Tensor ConjugateGradient(const std::function<torch::Tensor(const torch::Tensor&)>& product,
                                const torch::Tensor& b, int64_t iterations);

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
