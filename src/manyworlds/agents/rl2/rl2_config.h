// Configuration of RL2 (Duan et al. 2016) trained with PPO, as garage's
// RL2PPO. Defaults follow garage's Meta-World launchers (v2 branch,
// metaworld_examples/rl2_ppo_metaworld_ml10.py):
// GRU width 256, std in [0.5, 1.5], Adam 5e-4, clip 0.2, GAE 0.95, 10
// epochs, entropy "max" with coefficient 5e-6, advantages not centred, the
// linear feature baseline; 10 episodes per trial.
#ifndef MANYWORLDS_AGENTS_RL2_RL2_CONFIG_H_
#define MANYWORLDS_AGENTS_RL2_RL2_CONFIG_H_

#include <cstdint>
#include <string>

#include "manyworlds/core/visit_fields.h"

namespace manyworlds::agents {

struct Rl2Config {
  int64_t hidden_dim = 256;  // GRU width
  double init_std = 1.0;
  double min_std = 0.5;
  double max_std = 1.5;
  double lr = 5e-4;
  int64_t epochs = 10;
  int64_t minibatch_trials = 32;  // whole trials per minibatch (BPTT over the trial)
  double clip_range = 0.2;
  double max_grad_norm = 0.0;  // 0: no clipping
  double discount = 0.99;
  double gae_lambda = 0.95;
  bool center_advantages = false;
  std::string entropy_method = "max";  // regularized | max | none
  double entropy_coeff = 5e-6;
  // Episodes of one task variation per trial; the hidden state carries over
  // between them and is reset between trials. One training iteration
  // collects one trial in every env.
  int64_t episodes_per_trial = 10;
  // The reward as the policy sees it in its input is reward * this
  // (Meta-World v3's recurrent wrapper divides by 10; the return the PPO
  // objective maximises is not scaled).
  double context_reward_scale = 1.0;
  uint64_t seed = 0;

  template <class F>
  void VisitFields(F&& f) {
    MANYWORLDS_VISIT_FIELDS(f, hidden_dim, init_std, min_std, max_std, lr, epochs, minibatch_trials,
                            clip_range, max_grad_norm, discount, gae_lambda, center_advantages,
                            entropy_method, entropy_coeff, episodes_per_trial, context_reward_scale,
                            seed);
  }
  // Rounds of every env collected for one update: one trial.
  int64_t RoundsPerIteration() const { return episodes_per_trial; }
  // Throws ConfigError naming the first bad field (prefix "agent.").
  void Validate() const;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_RL2_RL2_CONFIG_H_
