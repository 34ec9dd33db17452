// Configuration of PPO (see ppo.h); torch-free so that configs can be
// read and validated without the networks.
#ifndef MANYWORLDS_AGENTS_PPO_PPO_CONFIG_H_
#define MANYWORLDS_AGENTS_PPO_PPO_CONFIG_H_

#include <cstdint>

#include "manyworlds/agents/policy_gradient/policy_gradient_config.h"
#include "manyworlds/core/visit_fields.h"

namespace manyworlds::agents {

struct PpoConfig : PolicyGradientConfig {
  double lr = 2.5e-4;  // policy Adam (garage torch PPO)
  int64_t epochs = 10;
  int64_t minibatch_size = 64;
  double clip_range = 0.2;
  double max_grad_norm = 0.0;  // 0 = no clipping (garage's default)

  template <class F>
  void VisitFields(F&& f) {
    PolicyGradientConfig::VisitFields(f);
    MANYWORLDS_VISIT_FIELDS(f, lr, epochs, minibatch_size, clip_range, max_grad_norm);
  }
  void Validate() const;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_PPO_PPO_CONFIG_H_
