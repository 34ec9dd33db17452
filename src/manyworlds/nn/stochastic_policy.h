// Policies of the on-policy family (PPO, TRPO, MAML, RL2): a diagonal
// Gaussian over Box actions or a categorical over Discrete actions, both
// from one MLP over a flat parameter buffer (so TRPO's flat gradient,
// conjugate gradient and line search, and MAML's fast weights, are
// operations on one vector).
//
// Gaussian: the MLP (tanh hidden layers, linear output) gives the mean; the
// log standard deviation is a learned state-independent vector, clamped to
// [log min_std, log max_std] (garage's GaussianMLPPolicy with min_std /
// max_std; the Meta-World launchers use 0.5 and 1.5). The clamp is a hard
// clamp, as garage's, so its gradient is zero outside the range. Actions are
// unbounded samples; the caller clips them to the action box (the env sees
// clip(a, -1, 1) scaled to its bounds), and log-probabilities are those of
// the unclipped sample, as in garage and Stable-Baselines3.
//
// Categorical: the MLP gives logits over num_actions; actions are indices
// held in a float column (the env API's Discrete convention).
//
// Initialisation: orthogonal, hidden gain sqrt(2), output gain 0.01, zero
// biases (Stable-Baselines3's on-policy scheme; garage uses Xavier-uniform).
// With num_heads > 1 the output layer holds one head per task, chosen per row.
#ifndef MANYWORLDS_NN_STOCHASTIC_POLICY_H_
#define MANYWORLDS_NN_STOCHASTIC_POLICY_H_

#include <cstdint>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"
#include "manyworlds/nn/mlp.h"

namespace manyworlds::nn {

// A batch of action distributions (B rows).
struct ActionDistribution {
  bool discrete = false;
  torch::Tensor mean;     // (B, A) Gaussian
  torch::Tensor log_std;  // (B, A) Gaussian (broadcast of the learned vector)
  torch::Tensor logits;   // (B, n) categorical, normalised (log-softmax)

  // log pi(a) (B); actions (B, A) floats, or (B, 1) indices for categorical.
  torch::Tensor LogProb(const torch::Tensor& actions) const;
  torch::Tensor Entropy() const;  // (B)
  // KL(this || other) per row (B), differentiable in both.
  torch::Tensor KlTo(const ActionDistribution& other) const;
  // Samples (B, A) or (B, 1) indices as floats.
  torch::Tensor Sample(at::Generator& generator) const;
  // The mean, or the most likely index.
  torch::Tensor Mode() const;
  // A copy with no autograd history (the "old" policy of PPO and TRPO).
  ActionDistribution Detached() const;
};

// Orthogonal init with the given gain for every weight (w0, b0, ...) and
// zero biases; the last weight gets output_gain.
void InitOnPolicyMlp(at::ArrayRef<torch::Tensor> params, double hidden_gain, double output_gain,
                     at::Generator& generator);

struct StochasticPolicyOptions {
  int64_t input_dim = 0;
  int64_t action_dim = 0;   // Box: action size; Discrete: 1
  int64_t num_actions = 0;  // > 0: categorical over this many actions
  int64_t hidden_dim = 64;
  int64_t num_layers = 2;
  double init_std = 1.0;
  double min_std = 0.5;
  double max_std = 1.5;
  int64_t num_heads = 1;
  // Gain of the output layer's orthogonal init (0.01: near-uniform first
  // actions; task encoders use 1 so that tasks start apart).
  double output_gain = 0.01;
  // tanh on the Gaussian mean (bounded latents of TE-PPO's encoders).
  bool tanh_mean = false;
};

class StochasticPolicyImpl : public FlatModule {
 public:
  // Throws ConfigError on bad sizes or std bounds.
  StochasticPolicyImpl(const StochasticPolicyOptions& options, at::Generator& generator);

  // x (B, input_dim); head (B) int64 when num_heads > 1. With explicit
  // params (layout order of params()) this is the functional form.
  ActionDistribution Forward(const torch::Tensor& x, const torch::Tensor& head,
                             at::ArrayRef<torch::Tensor> params) const;
  ActionDistribution Forward(const torch::Tensor& x, const torch::Tensor& head = {}) const {
    return Forward(x, head, params());
  }

  bool discrete() const { return options_.num_actions > 0; }
  const StochasticPolicyOptions& options() const { return options_; }

 private:
  StochasticPolicyOptions options_;
  size_t mlp_tensors_ = 0;
  int64_t head_dim_ = 0;
};
TORCH_MODULE(StochasticPolicy);

// A value function: tanh MLP -> 1 (per head). Forward gives (B).
class ValueNetworkImpl : public FlatModule {
 public:
  ValueNetworkImpl(int64_t input_dim, int64_t hidden_dim, int64_t num_layers, int64_t num_heads,
                   at::Generator& generator);
  torch::Tensor Forward(const torch::Tensor& x, const torch::Tensor& head,
                        at::ArrayRef<torch::Tensor> params) const;
  torch::Tensor Forward(const torch::Tensor& x, const torch::Tensor& head = {}) const {
    return Forward(x, head, params());
  }

 private:
  int64_t num_heads_;
};
TORCH_MODULE(ValueNetwork);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_STOCHASTIC_POLICY_H_
