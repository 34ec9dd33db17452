#include "manyworlds/agents/policy_gradient/policy_gradient_config.h"

#include <algorithm>

#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/task_conditioning.h"

namespace manyworlds::agents {
void PolicyGradientConfig::Validate() const {
  const auto& archs = nn::TaskConditioningArchitectures();
  RequireField(std::find(archs.begin(), archs.end(), architecture) != archs.end(), "architecture",
               "one of mlp, multihead, task_encoder, moe", architecture);
  RequireField(task_embedding_dim > 0 && task_embedding_dim <= 65536, "task_embedding_dim",
               "in [1, 65536]", task_embedding_dim);
  RequireField(num_experts > 0 && num_experts <= 1024, "num_experts", "in [1, 1024]", num_experts);
  RequireField(encoder_dim > 0 && encoder_dim <= 65536, "encoder_dim", "in [1, 65536]",
               encoder_dim);
  RequireField(hidden_dim > 0 && hidden_dim <= 65536, "hidden_dim", "in [1, 65536]", hidden_dim);
  RequireField(num_layers >= 0 && num_layers <= 64, "num_layers", "in [0, 64]", num_layers);
  RequireStdBounds("", min_std, max_std, init_std);
  RequireField(baseline == "mlp" || baseline == "linear", "baseline", "one of mlp, linear",
               baseline);
  RequireField(vf_hidden_dim > 0 && vf_hidden_dim <= 65536, "vf_hidden_dim", "in [1, 65536]",
               vf_hidden_dim);
  RequireField(vf_num_layers >= 0 && vf_num_layers <= 64, "vf_num_layers", "in [0, 64]",
               vf_num_layers);
  RequireField(FinitePositive(vf_lr), "vf_lr", "finite and > 0", vf_lr);
  RequireDiscountAndLambda(discount, gae_lambda);
  RequireEntropyTerm(entropy_method, entropy_coeff);
  RequireField(rollout_rounds >= 1 && rollout_rounds <= 100000, "rollout_rounds", "in [1, 100000]",
               rollout_rounds);
}

}  // namespace manyworlds::agents
