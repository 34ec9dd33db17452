#include "manyworlds/agents/hipbmdp/hipbmdp.h"

#include <cmath>
#include <string>

#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"

namespace manyworlds::agents {

HipBmdpConfig::HipBmdpConfig() {
  architecture = "task_encoder";
  critic_trains_task_encoder = false;
  task_embedding_dim = 50;
  task_encoder_hidden = 100;
  task_encoder_layers = 1;
}

void HipBmdpConfig::Validate() const {
  DeepMdpConfig::Validate();
  RequireField(std::isfinite(contrastive_alpha) && contrastive_alpha >= 0, "contrastive_alpha",
               "finite and >= 0", contrastive_alpha);
  RequireField(architecture == "task_encoder" && !critic_trains_task_encoder, "architecture",
               "task_encoder with critic_trains_task_encoder false (theta is trained by the "
               "model losses)",
               architecture + (critic_trains_task_encoder ? " (critic_trains_task_encoder true)"
                                                          : ""));
}

HipBmdpLearner::HipBmdpLearner(const HipBmdpConfig& config, int64_t obs_dim, int64_t action_dim,
                               int64_t num_tasks, const std::vector<int64_t>& frame_shape)
    : DeepMdpLearner(Validated(config), obs_dim, action_dim, num_tasks, frame_shape,
                     config.contrastive_alpha) {}

}  // namespace manyworlds::agents
