// Configuration of TRPO (see trpo.h); torch-free so that configs can be
// read and validated without the networks.
#ifndef MANYWORLDS_AGENTS_TRPO_TRPO_CONFIG_H_
#define MANYWORLDS_AGENTS_TRPO_TRPO_CONFIG_H_

#include <cstdint>

#include "manyworlds/agents/policy_gradient/policy_gradient_config.h"
#include "manyworlds/core/visit_fields.h"

namespace manyworlds::agents {

struct TrpoConfig : PolicyGradientConfig {
  double max_kl = 0.01;
  int64_t cg_iters = 10;
  double cg_damping = 1e-5;  // garage's hvp reg_coeff
  double backtrack_ratio = 0.8;
  int64_t max_backtracks = 15;
  int64_t vf_epochs = 10;
  int64_t vf_minibatch_size = 64;

  template <class F>
  void VisitFields(F&& f) {
    PolicyGradientConfig::VisitFields(f);
    MANYWORLDS_VISIT_FIELDS(f, max_kl, cg_iters, cg_damping, backtrack_ratio, max_backtracks,
                            vf_epochs, vf_minibatch_size);
  }
  void Validate() const;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_TRPO_TRPO_CONFIG_H_
