// Settings shared by the policy-gradient family (PPO, TRPO; later the inner
// learners of MAML and RL2). Defaults are garage's torch on-policy defaults
// where it has them (discount 0.99, GAE lambda 0.95, centred advantages,
// Gaussian MLP policy with tanh hidden layers, std in [0.5, 1.5] as the
// Meta-World launchers clamp it); the network sizes are small ones, configs
// set the published sizes.
//
// Task conditioning ("architecture"), built from the task index inside the
// learner (observations never carry a task id):
//   "mlp"        one-hot task id appended to the observation when there are
//                several tasks (MT-PPO / MT-TRPO as in the Meta-World paper);
//   "multihead"  shared trunk, one output head per task for policy and value;
//   "task_encoder" a learned task encoding (width task_embedding_dim)
//                appended to the observation (MTRL's task encoder);
//   "moe"        CARE's mixture of num_experts state encoders (width
//                encoder_dim) weighted by attention from the task encoding.
// The learned encoders belong to the policy: they are trained by the policy
// objective (PPO: their own Adam at lr; TRPO: inside the natural-gradient
// step) and the value function reads their output detached
// (nn/task_conditioning.h).
// pcgrad: the policy's (and value network's) per-task gradients are combined
// by PCGrad (nn/pcgrad.h) before each step; for TRPO, the surrogate's
// gradient that the conjugate gradient solves against.
// Baseline: "mlp" (a tanh value network trained by regression on the
// lambda-returns) or "linear" (garage's LinearFeatureBaseline).
// Entropy: "regularized" subtracts entropy_coeff * H from the policy loss;
// "max" adds entropy_coeff * (-log pi(a|s)) to every reward before GAE
// (garage's entropy_method='max' with use_neg_logli_entropy); "none".
#ifndef MANYWORLDS_AGENTS_POLICY_GRADIENT_POLICY_GRADIENT_CONFIG_H_
#define MANYWORLDS_AGENTS_POLICY_GRADIENT_POLICY_GRADIENT_CONFIG_H_

#include <cstdint>
#include <string>

#include "manyworlds/core/visit_fields.h"

namespace manyworlds::agents {

struct PolicyGradientConfig {
  std::string architecture = "mlp";  // mlp | multihead | task_encoder | moe
  int64_t task_embedding_dim = 50;   // task_encoder, moe
  int64_t num_experts = 4;           // moe
  int64_t encoder_dim = 50;          // moe
  bool pcgrad = false;
  int64_t hidden_dim = 64;
  int64_t num_layers = 2;
  double init_std = 1.0;
  double min_std = 0.5;
  double max_std = 1.5;
  std::string baseline = "mlp";  // mlp | linear
  int64_t vf_hidden_dim = 64;
  int64_t vf_num_layers = 2;
  double vf_lr = 2.5e-4;
  double discount = 0.99;
  double gae_lambda = 0.95;
  bool center_advantages = true;  // normalise advantages to mean 0, std 1
  std::string entropy_method = "regularized";  // regularized | max | none
  double entropy_coeff = 0.0;
  // Rounds (one episode length of every env) collected per iteration.
  int64_t rollout_rounds = 1;
  uint64_t seed = 0;

  // Calls f(name, member) for every field, in documentation order.
  template <class F>
  void VisitFields(F&& f) {
    MANYWORLDS_VISIT_FIELDS(f, architecture, task_embedding_dim, num_experts, encoder_dim, pcgrad,
                            hidden_dim, num_layers, init_std, min_std, max_std, baseline,
                            vf_hidden_dim, vf_num_layers, vf_lr, discount, gae_lambda,
                            center_advantages, entropy_method, entropy_coeff, rollout_rounds, seed);
  }
  // Rounds of every env collected for one update (the on-policy loop's
  // iteration).
  int64_t RoundsPerIteration() const { return rollout_rounds; }
  // Throws ConfigError naming the first bad field (prefix "agent.").
  void Validate() const;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_POLICY_GRADIENT_POLICY_GRADIENT_CONFIG_H_
