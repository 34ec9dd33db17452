#include "manyworlds/agents/sac/sac_config.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/task_trunks.h"

namespace manyworlds::agents {
namespace {

template <typename T>
void Require(bool ok, const char* field, const char* allowed, T value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "SacConfig." << field << " must be " << allowed << ", got " << value;
  throw ConfigError(msg.str());
}

bool Finite(double x) { return std::isfinite(x); }

}  // namespace

void SacConfig::Validate() const {
  // the bounds of every other agent's networks (a typo of 2^63 layers was taken)
  Require(hidden_dim > 0 && hidden_dim <= 65536, "hidden_dim", "in [1, 65536]", hidden_dim);
  Require(num_layers >= 0 && num_layers <= 64, "num_layers", "in [0, 64]", num_layers);
  Require(Finite(actor_lr) && actor_lr > 0, "actor_lr", "finite and > 0", actor_lr);
  Require(Finite(critic_lr) && critic_lr > 0, "critic_lr", "finite and > 0", critic_lr);
  Require(Finite(alpha_lr) && alpha_lr >= 0, "alpha_lr", "finite and >= 0", alpha_lr);
  Require(adam_beta1 >= 0 && adam_beta1 < 1, "adam_beta1", "in [0, 1)", adam_beta1);
  Require(adam_beta2 >= 0 && adam_beta2 < 1, "adam_beta2", "in [0, 1)", adam_beta2);
  Require(discount >= 0 && discount <= 1, "discount", "in [0, 1]", discount);
  Require(tau > 0 && tau <= 1, "tau", "in (0, 1]", tau);
  Require(Finite(init_temperature) && init_temperature > 0, "init_temperature",
          "finite and > 0", init_temperature);
  Require(batch_size > 0, "batch_size", "> 0", batch_size);
  if (target_entropy) {
    Require(Finite(*target_entropy), "target_entropy", "finite", *target_entropy);
  }
  Require(Finite(log_std_min) && Finite(log_std_max) && log_std_min < log_std_max,
          "log_std_min", "finite and < log_std_max", log_std_min);
  Require(actor_update_freq >= 1, "actor_update_freq", ">= 1", actor_update_freq);
  Require(critic_target_update_freq >= 1, "critic_target_update_freq", ">= 1",
          critic_target_update_freq);
  Require(!std::isnan(max_critic_loss), "max_critic_loss", "a number", max_critic_loss);
  const std::vector<std::string>& archs = SacArchitectures();
  if (std::find(archs.begin(), archs.end(), architecture) == archs.end()) {
    std::string allowed;
    for (const std::string& a : archs) allowed += (allowed.empty() ? "" : ", ") + a;
    throw ConfigError("SacConfig.architecture must be one of " + allowed + ", got '" +
                      architecture + "'");
  }
  Require(task_embedding_dim > 0, "task_embedding_dim", "> 0", task_embedding_dim);
  Require(task_encoder_hidden >= 0 && task_encoder_hidden <= 65536, "task_encoder_hidden",
          "in [0, 65536] (0: task_embedding_dim)", task_encoder_hidden);
  Require(task_encoder_layers >= 0 && task_encoder_layers <= 16, "task_encoder_layers",
          "in [0, 16]", task_encoder_layers);
  Require(critic_trains_task_encoder || architecture == "task_encoder",
          "critic_trains_task_encoder", "true unless architecture is task_encoder",
          critic_trains_task_encoder);
  Require(num_experts >= 1, "num_experts", ">= 1", num_experts);
  Require(encoder_dim > 0, "encoder_dim", "> 0", encoder_dim);
  Require(num_modules >= 1 && num_modules <= 64, "num_modules", "in [1, 64]", num_modules);
  Require(module_layers >= 2 && module_layers <= 16, "module_layers", "in [2, 16]",
          module_layers);
  Require(module_hidden > 0 && module_hidden <= 65536, "module_hidden", "in [1, 65536]",
          module_hidden);
  Require(routing_layers >= 1 && routing_layers <= 16, "routing_layers", "in [1, 16]",
          routing_layers);
  Require(routing_hidden > 0 && routing_hidden <= 65536, "routing_hidden", "in [1, 65536]",
          routing_hidden);
  Require(num_param_sets >= 1 && num_param_sets <= 64, "num_param_sets", "in [1, 64]",
          num_param_sets);
  Require(!std::isnan(paco_reset_threshold), "paco_reset_threshold", "a number",
          paco_reset_threshold);
  Require(task_metadata.empty() || architecture == "task_encoder" || architecture == "moe",
          "task_metadata", "empty unless architecture is task_encoder or moe (it replaces their "
          "learned task table)", "'" + task_metadata + "' with architecture " + architecture);
  Require(!gradnorm || architecture == "mlp" || architecture == "task_encoder" ||
              architecture == "moe",
          "gradnorm", "false unless architecture is mlp, task_encoder or moe (it balances "
          "gradients in a last layer all tasks share)", architecture);
  Require(!(gradnorm && pcgrad), "gradnorm", "false when pcgrad is on (one gradient "
          "manipulation at a time)", gradnorm);
  Require(std::isfinite(gradnorm_alpha) && gradnorm_alpha >= 0, "gradnorm_alpha",
          "finite and >= 0", gradnorm_alpha);
  Require(std::isfinite(gradnorm_lr) && gradnorm_lr > 0, "gradnorm_lr", "finite and > 0",
          gradnorm_lr);
  Require(!task_reweight || disentangled_alpha, "task_reweight",
          "false unless disentangled_alpha is true (it weighs tasks by their own temperatures)",
          task_reweight);
  Require(encoder_feature_dim >= 1 && encoder_feature_dim <= 65536, "encoder_feature_dim",
          "in [1, 65536]", encoder_feature_dim);
  Require(num_filters >= 1 && num_filters <= 1024, "num_filters", "in [1, 1024]", num_filters);
  Require(num_conv_layers >= 1 && num_conv_layers <= 16, "num_conv_layers", "in [1, 16]",
          num_conv_layers);
  Require(encoder_tau > 0 && encoder_tau <= 1, "encoder_tau", "in (0, 1]", encoder_tau);
  Require(update_shards >= 1 && update_shards <= 64, "update_shards", "in [1, 64]",
          update_shards);
  Require(update_threads >= 0 && update_threads <= 64, "update_threads",
          "in [0, 64] (0: one per shard, at most one per core)", update_threads);
}

const std::vector<std::string>& SacArchitectures() {
  // The index of a name is its code in checkpoints: append only.
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list = {"mlp", "multihead", "task_encoder", "moe"};
    for (const nn::TaskTrunkInfo& trunk : nn::TaskTrunks()) list.push_back(trunk.name);
    return list;
  }();
  return names;
}

}  // namespace manyworlds::agents
