// Configuration of PEARL (Rakelly et al. 2019, "Efficient Off-Policy
// Meta-Reinforcement Learning via Probabilistic Context Variables").
// Defaults are the original implementation's (oyster's configs/default.py,
// network sizes from its launch_experiment.py): latent 5, networks 3 x 300, encoder 3 x 200, all
// learning rates 3e-4, reward scale 5, KL weight 0.1, information bottleneck
// on, the context is (obs, action, reward) without the next observation
// (oyster's default; the option is not offered), meta-batch 16 tasks, RL batch 256
// and context batch 64 per task, 2000 gradient steps per iteration, policy
// mean and log-std regularisers 1e-3, discount 0.99, tau 0.005.
//
// Collection is counted in episodes per env instead of steps per task (the
// loop steps every env in lockstep, experiments/loops/pearl_loop.cc): oyster's
// 400 prior and 400 extra-posterior steps of 200-step episodes are 2 and 2.
#ifndef MANYWORLDS_AGENTS_PEARL_PEARL_CONFIG_H_
#define MANYWORLDS_AGENTS_PEARL_PEARL_CONFIG_H_

#include <cstdint>

#include "manyworlds/core/visit_fields.h"

namespace manyworlds::agents {

struct PearlConfig {
  int64_t latent_dim = 5;
  int64_t hidden_dim = 300;  // policy, Q and V networks
  int64_t num_layers = 3;
  int64_t encoder_hidden_dim = 200;
  int64_t encoder_num_layers = 3;
  double policy_lr = 3e-4;
  double qf_lr = 3e-4;
  double vf_lr = 3e-4;
  double context_lr = 3e-4;
  double discount = 0.99;
  double tau = 0.005;  // Polyak rate of the target value network
  // Rewards in the critic target are multiplied by this; with the fixed
  // entropy weight 1 it sets the trade-off between return and entropy.
  double reward_scale = 5.0;
  double kl_lambda = 0.1;
  // true: the encoder outputs a Gaussian per transition and the posterior is
  // their product; false: z is the mean of the per-transition outputs.
  bool use_information_bottleneck = true;
  double policy_mean_reg = 1e-3;
  double policy_std_reg = 1e-3;
  double log_std_min = -20.0;
  double log_std_max = 2.0;
  int64_t meta_batch = 16;            // tasks per gradient step
  int64_t batch_size = 256;           // RL transitions per task per step
  int64_t embedding_batch_size = 64;  // context transitions per task per step
  int64_t updates_per_iteration = 2000;
  // Episodes each env collects per iteration, all on one task: with z drawn
  // from the prior (to the RL and the encoder buffer), with z from the
  // posterior of the task's encoder buffer (to both), and with z from that
  // posterior to the RL buffer only.
  int64_t prior_episodes = 2;
  int64_t posterior_episodes = 0;
  int64_t extra_posterior_episodes = 2;
  uint64_t seed = 0;

  template <class F>
  void VisitFields(F&& f) {
    MANYWORLDS_VISIT_FIELDS(f, latent_dim, hidden_dim, num_layers, encoder_hidden_dim,
                            encoder_num_layers, policy_lr, qf_lr, vf_lr, context_lr, discount, tau,
                            reward_scale, kl_lambda, use_information_bottleneck, policy_mean_reg,
                            policy_std_reg, log_std_min, log_std_max, meta_batch, batch_size,
                            embedding_batch_size, updates_per_iteration, prior_episodes,
                            posterior_episodes, extra_posterior_episodes, seed);
  }
  // Episodes per env in one iteration.
  int64_t episodes_per_iteration() const {
    return prior_episodes + posterior_episodes + extra_posterior_episodes;
  }
  // Throws ConfigError naming the first bad field (prefix "agent.").
  void Validate() const;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_PEARL_PEARL_CONFIG_H_
