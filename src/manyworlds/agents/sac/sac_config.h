// Configuration of (multi-task) SAC. Defaults are MTRL's Meta-World MT10
// ones (agent=state_sac with setup=metaworld): 3 x 400 actor and critics, Adam 3e-4 with betas
// (0.9, 0.999), discount 0.99, tau 0.005, initial temperature 1.0, batch 128
// (MTRL's MT10 command uses 128 per task), target entropy -|A|, log-std in
// [-20, 2], actor and target updated every step.
//
// Task conditioning (`architecture`); the learner builds it from the task
// index, observations never carry a task id:
//   "mlp"          MT-SAC: one-hot task id appended to the observation
//                  inside the learner (only when num_tasks > 1);
//   "multihead"    shared trunk, one output head per task for the actor and
//                  both critics (all heads one product, chosen by task);
//   "task_encoder" learned task encoding (Embedding -> ReLU -> MLP, width
//                  task_embedding_dim) concatenated to the observation,
//                  trained through the critic loss only (the actor sees it
//                  detached), as MTRL's task encoder;
//   "moe"          CARE: num_experts state encoders (output encoder_dim)
//                  mixed by softmax attention weights computed from the
//                  task encoding; actor and critics see [mixture, task
//                  encoding]. The encoders are trained through the critic
//                  loss; the actor sees them detached (MTRL ties the actor's
//                  encoder to the critic's).
//   "soft_modular", "paco", "moore"
//                  networks whose structure depends on the task, for the
//                  actor and both critics (nn/task_trunks.h): Soft
//                  Modularization's routed modules, PaCo's per-task
//                  combinations of shared parameter sets, MOORE's
//                  orthogonal experts with one head per task. The
//                  observation goes in without a one-hot.
// task_reweight (Soft Modularization's trainer): each sample's critic and
// actor loss is multiplied by num_tasks * softmax(-log alpha)[task], so
// tasks whose temperature is still high weigh less; needs
// disentangled_alpha.
// paco_reset_threshold (PaCo's trainer): a task whose critic loss (its mean
// squared TD error, both critics summed) exceeds it is left out of the update
// and its task weights in the actor and critic are reset to a random convex
// combination of the other tasks' (`mask_extreme_task`,
// `reset_task_method="interpolate"`); <= 0 disables.
// task_metadata (CARE): a JSON file of fixed task vectors, e.g. embedded
// task descriptions (data/task_descriptions/metaworld_embeddings.json, its
// "tasks" object: task name -> {"embedding": [...]}); the task encoder of
// "task_encoder" and "moe" then starts from each task's vector instead of a
// learned table (nn/task_encoder.h). Empty: the learned table.
// gradnorm (Chen et al., ICML 2018; MTRL's gradnorm agents): the critic and
// actor losses become sums of per-task losses with learned weights w_t
// (starting at 1, kept summing to num_tasks); each update moves w by Adam on
// sum_t |w_t G_t - mean(w G) r_t^gradnorm_alpha|, G_t the norm of task t's
// loss gradient in the networks' last layer and r_t its loss relative to its
// first, over the mean of those. For the architectures whose last layer is
// shared by all tasks (mlp, task_encoder, moe). MTRL's version compares with
// the previous update's loss instead of the first and never renormalises
// (its renormalisation assigns a local); we follow the paper.
// pcgrad: per-task gradients of the critic and actor losses combined by
// PCGrad (nn/pcgrad.h) before the fused Adam steps.
// Pixel observations (the learner is given a frame shape: obs=pixels envs):
// the frames go through a convolutional encoder (nn/pixel_encoder.h:
// num_conv_layers x num_filters, encoder_feature_dim features; MTRL's
// 4 x 32 -> 50) whose features replace the observation in everything above.
// The critic loss trains it (with the critics' optimizer settings), the
// actor sees its features detached, the target critics read a target copy
// updated with encoder_tau (MTRL: 0.05) every critic_target_update_freq
// updates. MTRL's actor has an encoder of its own whose convolutions are
// tied to the critic's and whose linear and LayerNorm layers its optimizer
// never steps; ours reads the critic's whole encoder instead (one encoder
// pass per batch instead of two; the features are the same up to that
// untrained projection).
#ifndef MANYWORLDS_AGENTS_SAC_SAC_CONFIG_H_
#define MANYWORLDS_AGENTS_SAC_SAC_CONFIG_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "manyworlds/core/visit_fields.h"

namespace manyworlds::agents {

struct SacConfig {
  int64_t hidden_dim = 400;
  int64_t num_layers = 3;  // hidden layers of actor and critics
  double actor_lr = 3e-4;
  double critic_lr = 3e-4;
  double alpha_lr = 3e-4;
  double adam_beta1 = 0.9;
  double adam_beta2 = 0.999;
  double discount = 0.99;
  double tau = 0.005;  // Polyak factor of the target critics
  double init_temperature = 1.0;
  int64_t batch_size = 128;  // read by the caller that samples batches
  // Unset: -action_dim (MTRL / pytorch_sac).
  std::optional<double> target_entropy;
  // One temperature per task, chosen by Batch.task_index (MTRL's
  // should_use_disentangled_alpha); otherwise one shared temperature.
  bool disentangled_alpha = false;
  double log_std_min = -20.0;
  double log_std_max = 2.0;
  int64_t actor_update_freq = 1;          // actor and alpha every k updates
  int64_t critic_target_update_freq = 1;  // Polyak every k updates
  // MTRL stops when the critic loss exceeds this (divergence); <= 0 disables.
  double max_critic_loss = 1e8;
  uint64_t seed = 0;  // initialisation and action sampling

  // Multi-task variants (see the top of this file).
  // mlp | multihead | task_encoder | moe | soft_modular | paco | moore
  std::string architecture = "mlp";
  int64_t task_embedding_dim = 50;   // task_encoder and moe
  // The task encoder's MLP after its embedding (0: task_embedding_dim wide;
  // MTRL's TaskEncoder: 2 layers of 50; HiP-BMDP's ThetaModel: 1 of 100).
  int64_t task_encoder_hidden = 0;
  int64_t task_encoder_layers = 2;
  // false: the critic loss leaves the task encoder alone and the networks
  // read its encodings detached; the learner's owner trains it (HiP-BMDP,
  // whose losses_to_train omit the critic).
  bool critic_trains_task_encoder = true;
  int64_t num_experts = 4;  // moe, moore (CARE's and MOORE's MT10 commands use 4)
  int64_t encoder_dim = 50;          // moe: output (and hidden) width of the experts
  bool pcgrad = false;
  bool gradnorm = false;
  double gradnorm_alpha = 1.0;  // MTRL's config/agent/components/gradnorm.yaml
  double gradnorm_lr = 1e-6;    // MTRL's (mtrl/agent/gradnorm.py hard-codes it)
  // soft_modular (the authors' MT10 config modular_2_2_2_256: 2 layers of 2
  // modules of width 256, a routing MLP of 2 layers of 256; its base MLP
  // uses hidden_dim).
  int64_t num_modules = 2;
  int64_t module_layers = 2;
  int64_t module_hidden = 256;
  int64_t routing_layers = 2;
  int64_t routing_hidden = 256;
  int64_t num_param_sets = 5;           // paco (its MT10 config: 5)
  double paco_reset_threshold = 3000.0;  // paco (its MT10 config: task_loss_threshold 3e3)
  bool task_reweight = false;
  std::string task_metadata;  // task_encoder, moe: CARE's task metadata file
  // Pixel observations (MTRL's pixel agents: config/agent/sac_ae.yaml).
  int64_t encoder_feature_dim = 50;
  int64_t num_filters = 32;
  int64_t num_conv_layers = 4;
  double encoder_tau = 0.05;

  // Data-parallel updates: each update splits its batch into update_shards
  // parts whose gradients are computed at once on update_threads threads
  // (0: one per shard, at most one per core) and summed in shard order.
  // Results depend on update_shards (the order of floating-point sums), not
  // on update_threads or the machine. PCGrad updates run as one shard. On
  // the 2-core development machine 2 shards were slower than one shard with
  // 2 BLAS threads (docs/benchmarks.md), hence the default of 1.
  int64_t update_shards = 1;
  int64_t update_threads = 0;

  // Every config key, in the order the docs list them (reading, printing
  // and overrides go through this one list).
  template <class F>
  void VisitFields(F&& f) {
    MANYWORLDS_VISIT_FIELDS(f, hidden_dim, num_layers, actor_lr, critic_lr, alpha_lr, adam_beta1,
                            adam_beta2, discount, tau, init_temperature, batch_size, target_entropy,
                            disentangled_alpha, log_std_min, log_std_max, actor_update_freq,
                            critic_target_update_freq, max_critic_loss, seed, architecture,
                            task_embedding_dim, task_encoder_hidden, task_encoder_layers,
                            critic_trains_task_encoder, num_experts, encoder_dim, pcgrad, gradnorm,
                            gradnorm_alpha, gradnorm_lr, num_modules,
                            module_layers, module_hidden, routing_layers, routing_hidden,
                            num_param_sets, paco_reset_threshold, task_reweight, task_metadata,
                            encoder_feature_dim, num_filters, num_conv_layers, encoder_tau,
                            update_shards,
                            update_threads);
  }
  // Throws ConfigError naming the first bad field and its allowed range.
  void Validate() const;
};

// The allowed values of SacConfig::architecture, in documentation order.
const std::vector<std::string>& SacArchitectures();

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_SAC_SAC_CONFIG_H_
