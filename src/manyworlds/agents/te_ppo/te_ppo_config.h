// Configuration of TE-PPO (see te_ppo.h); torch-free so that configs can be
// read and validated without the networks. Defaults are garage's TEPPO
// MT10 launcher's where our networks can express them (v2 branch,
// metaworld_examples/te_ppo_metaworld_mt10.py):
// latent 4, inference window 6, encoder std in [1e-6, 0.2] from 0.1,
// inference std from 2.0, policy lr 1e-3, clip 0.2, 10 epochs, policy
// entropy 2e-2 (softplus), encoder entropy 2e-4, inference cross-entropy
// 5e-2, centred advantages, inference Adam 1e-3 over 10 epochs of 64.
// Garage's layer widths (policy 32-16, encoder 20-20, inference 20-10)
// become one width per network here (hidden_dim, encoder_hidden_dim,
// inference_hidden_dim x num_layers).
#ifndef MANYWORLDS_AGENTS_TE_PPO_TE_PPO_CONFIG_H_
#define MANYWORLDS_AGENTS_TE_PPO_TE_PPO_CONFIG_H_

#include <cstdint>

#include "manyworlds/agents/ppo/ppo_config.h"
#include "manyworlds/core/visit_fields.h"

namespace manyworlds::agents {

struct TePpoConfig : PpoConfig {
  TePpoConfig() {
    hidden_dim = 32;
    lr = 1e-3;
    minibatch_size = 32;
    entropy_method = "max";
    entropy_coeff = 2e-2;
    baseline = "linear";  // garage: LinearMultiFeatureBaseline(obs, tasks, latents)
  }
  int64_t latent_dim = 4;
  int64_t encoder_hidden_dim = 20;
  int64_t encoder_num_layers = 2;
  double encoder_init_std = 0.1;
  double encoder_min_std = 1e-6;
  double encoder_max_std = 0.2;
  double encoder_entropy_coeff = 2e-4;
  int64_t inference_window = 6;  // observations, looking forward from each step
  int64_t inference_hidden_dim = 20;
  int64_t inference_num_layers = 2;
  double inference_init_std = 2.0;
  double inference_min_std = 1e-6;
  double inference_max_std = 10.0;
  double inference_lr = 1e-3;
  int64_t inference_epochs = 10;
  int64_t inference_minibatch_size = 64;
  double inference_ce_coeff = 5e-2;
  // softplus on the per-step entropy and cross-entropy reward terms (garage's
  // use_softplus_entropy, keeps them positive for small stds)
  bool softplus_entropy = true;

  template <class F>
  void VisitFields(F&& f) {
    PpoConfig::VisitFields(f);
    MANYWORLDS_VISIT_FIELDS(f, latent_dim, encoder_hidden_dim, encoder_num_layers, encoder_init_std,
                            encoder_min_std, encoder_max_std, encoder_entropy_coeff,
                            inference_window, inference_hidden_dim, inference_num_layers,
                            inference_init_std, inference_min_std, inference_max_std, inference_lr,
                            inference_epochs, inference_minibatch_size, inference_ce_coeff,
                            softplus_entropy);
  }
  void Validate() const;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_TE_PPO_TE_PPO_CONFIG_H_
