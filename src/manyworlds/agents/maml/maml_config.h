// Configuration of MAML with a TRPO outer step (Finn et al. 2017; garage's
// MAMLTRPO). Defaults follow garage's point and half-cheetah launchers
// where they have one (maml_trpo_half_cheetah_dir.py): Gaussian MLP policy 2 x 64 tanh with
// std in [0.5, 1.5], one inner vanilla policy-gradient step of lr 0.1, mean
// KL <= 0.01 for the outer TRPO step, GAE lambda 1, the linear feature
// baseline fitted per task instance, centred advantages. outer: "ppo" is
// garage's MAMLPPO instead: outer_epochs Adam steps (lr outer_lr, garage
// 1e-3) on the clipped post-adaptation surrogate (clip 0.5, garage's
// lr_clip_range), gradients through the inner step as for TRPO.
// baseline: "linear" is garage's LinearFeatureBaseline, fitted per task
// instance; "value_network" is an MLP value function (tanh, inputs obs and
// step / 100) reset to its initial weights and a fresh Adam before every
// per-task fit, then fitted for value_fit_steps full-batch steps on the
// task's discounted returns (standardised), so no task's fit leaks into
// another's. garage fits its GaussianMLPBaseline with its own optimizer;
// ours uses Adam.
#ifndef MANYWORLDS_AGENTS_MAML_MAML_CONFIG_H_
#define MANYWORLDS_AGENTS_MAML_MAML_CONFIG_H_

#include <cstdint>
#include <string>

#include "manyworlds/core/visit_fields.h"

namespace manyworlds::agents {

struct MamlConfig {
  int64_t hidden_dim = 64;
  int64_t num_layers = 2;
  double init_std = 1.0;
  double min_std = 0.5;
  double max_std = 1.5;
  double inner_lr = 0.1;
  // Episodes per task instance before adaptation, and as many after: an
  // iteration is 2 x episodes_per_task rounds, every env on one variation.
  int64_t episodes_per_task = 10;
  double discount = 0.99;
  double gae_lambda = 1.0;
  bool center_advantages = true;
  std::string outer = "trpo";  // trpo | ppo
  std::string baseline = "linear";  // linear | value_network
  int64_t value_hidden_dim = 32;    // value_network (garage's (32, 32))
  int64_t value_num_layers = 2;
  double value_lr = 1e-2;
  int64_t value_fit_steps = 50;
  double outer_lr = 1e-3;      // ppo
  int64_t outer_epochs = 1;    // ppo: Adam steps per iteration
  double clip_range = 0.5;     // ppo
  double max_kl = 0.01;
  int64_t cg_iters = 10;
  double cg_damping = 1e-5;
  double backtrack_ratio = 0.8;
  int64_t max_backtracks = 15;
  uint64_t seed = 0;

  template <class F>
  void VisitFields(F&& f) {
    MANYWORLDS_VISIT_FIELDS(f, hidden_dim, num_layers, init_std, min_std, max_std, inner_lr,
                            episodes_per_task, discount, gae_lambda, center_advantages, outer,
                            baseline, value_hidden_dim, value_num_layers, value_lr, value_fit_steps,
                            outer_lr, outer_epochs, clip_range, max_kl, cg_iters, cg_damping,
                            backtrack_ratio, max_backtracks, seed);
  }
  // Rounds of every env collected for one update: the episodes before and
  // after adaptation.
  int64_t RoundsPerIteration() const { return 2 * episodes_per_task; }
  // Throws ConfigError naming the first bad field (prefix "agent.").
  void Validate() const;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_MAML_MAML_CONFIG_H_
