// Soft actor-critic for one or many tasks (MTRL's MT-SAC structure and its
// multi-task variants).
//
//   SacLearner sac(config, obs_dim, action_dim, num_tasks);
//   Metrics m = sac.Update(batch);                       // one gradient step
//   torch::Tensor a = sac.Act(obs, task_index, /*deterministic=*/false);
//
// Observations never carry a task id: obs is the env observation (B,
// obs_dim) and the task is Batch.task_index / the task_index argument. The
// learner conditions on the task as config.architecture says (see
// sac_config.h): it builds the networks' input x(s, task) (the observation
// with a one-hot, a learned task encoding, or a CARE mixture encoding) and,
// for "multihead", picks each row's output head by task.
//
// One update, in MTRL's order:
//  1. critic target y = r + discount (1 - done) (min_j Q'_j(s', a') - alpha log pi(a'|s'))
//     with a' ~ pi(.|s') and the target critics (for "moe" also the target
//     copy of the mixture encoder), no gradient;
//  2. critic loss MSE(Q1, y) + MSE(Q2, y), one backward into the critics and
//     any encoders (task encoder, mixture encoder), fused Adam steps;
//  3. every actor_update_freq updates: actor loss mean(alpha log pi(a|s) -
//     min_j Q_j(s, a)) with the updated critics run on detached weights and
//     detached encodings (the backward reaches the action but computes no
//     critic or encoder gradients), and temperature loss mean(alpha (-log pi
//     - target_entropy)) whose gradient in log-alpha is computed in closed
//     form;
//  4. every critic_target_update_freq updates: Polyak update of the target
//     critics (and of the target mixture encoder, with the same tau; MTRL
//     uses a separate encoder_tau of 0.05 there).
// Temperatures are per task with disentangled_alpha, indexed by task_index.
// With task_reweight every sample's terms in the critic and actor losses are
// weighted by num_tasks * softmax(-log alpha)[task] (Soft Modularization).
// For "paco" with paco_reset_threshold > 0, tasks whose critic loss exceeds
// the threshold get weight 0 in this update (the critic phase is recomputed
// with them masked) and their task weights are reset after it (metric
// paco_resets: how many tasks).
//
// With config.pcgrad, steps 2 and 3 compute one gradient per task present in
// the batch (the mean loss over that task's samples), combine them with
// PCGrad (nn/pcgrad.h; random orders from generator()) and step with the
// combined gradient. The temperature update is unchanged. This costs one
// backward per task present.
//
// Metrics: critic_loss, q_mean, and on actor steps actor_loss, alpha (mean
// temperature used), alpha_loss, entropy (-mean log pi). With pcgrad also
// pcgrad_conflicts (fraction of ordered task pairs whose critic gradients
// conflict, g_i . g_j < 0) and, on actor steps, pcgrad_actor_conflicts.
//
// Data-parallel updates (config.update_shards > 1): the batch is split into
// contiguous shards; each shard computes its part of every loss and
// backpropagates it into gradient buffers of its own (nn::GradientReplica),
// the shards run at once on a worker pool with one-thread BLAS, and the
// buffers are summed in shard order before each optimizer step. All action
// noise is drawn for the whole batch before the split, so an update depends
// on update_shards but not on the number of threads.
//
// A prior (SetPrior; Distral's distilled policy) regularises the policy
// towards another one, pi_0, with weight c = prior.weight: the soft value
// becomes min Q - (alpha + c) log pi + c log pi_0 (the reward regulariser
// c log(pi_0 / pi) - alpha log pi of Teh et al. 2017, with the entropy
// weight alpha the learned temperature), and the actor loss
// (alpha + c) log pi(a|s) - c log pi_0(a|s) - min Q(s, a), gradients
// reaching pi_0's density through the reparameterised action only.
//
// The learner calls nn::ConfigureTorchThreads() (see nn/threads.h). Not
// thread-safe.
#ifndef MANYWORLDS_AGENTS_SAC_SAC_H_
#define MANYWORLDS_AGENTS_SAC_SAC_H_

#include <torch/torch.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "manyworlds/agents/actor.h"
#include "manyworlds/agents/batch.h"
#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/metrics.h"
#include "manyworlds/agents/sac/sac_config.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/gradnorm.h"
#include "manyworlds/nn/gaussian_policy.h"
#include "manyworlds/nn/pixel_encoder.h"
#include "manyworlds/nn/task_encoder.h"
#include "manyworlds/nn/twin_critic.h"
#include "manyworlds/nn/worker_pool.h"

namespace manyworlds::agents {

// r + discount * (1 - done) * (next_q - alpha * next_log_prob), elementwise
// over (B); alpha broadcasts ((B) or (1)).
torch::Tensor SoftTdTarget(const torch::Tensor& reward, const torch::Tensor& done,
                           const torch::Tensor& next_q, const torch::Tensor& next_log_prob,
                           const torch::Tensor& alpha, double discount);

// Adam with the config's betas (every SAC-family optimiser).
nn::AdamOptions SacAdamOptions(const SacConfig& config, double lr, double weight_decay = 0.0);
// The pixel encoder of a config for frames of frame_shape (C, H, W).
nn::PixelEncoderOptions SacPixelEncoderOptions(const SacConfig& config,
                                               const std::vector<int64_t>& frame_shape);
// frame_shape, or ConfigError naming `learner` when it is empty (a learner
// that only learns from frames).
const std::vector<int64_t>& RequireFrameShape(const std::vector<int64_t>& frame_shape,
                                              const char* learner);

// Another policy's log-density of squashed actions a = tanh(u) at raw
// observations obs (B, obs_dim), u (B, A) -> (B); differentiable in u.
// Called from several threads at once when updates are sharded.
struct PolicyPrior {
  double weight = 0.0;
  std::function<torch::Tensor(const torch::Tensor& obs, const torch::Tensor& u)> log_prob;
};

class SacLearner : public OffPolicyLearner, public Actor {
 public:
  // Validates the config (ConfigError) and the dims (> 0). task_metadata:
  // (num_tasks, D) fixed task vectors, required when config.task_metadata is
  // set (the caller reads the file: experiments' LoadTaskMetadata) and saved
  // in checkpoints (Load refuses other vectors). frame_shape (C, H, W): the
  // learner acts on pixel frames through a convolutional encoder (see
  // sac_config.h), reads Batch::pixels and next_pixels, and Act takes frames
  // (B, C, H, W) uint8; empty: it acts on the observation.
  SacLearner(const SacConfig& config, int64_t obs_dim, int64_t action_dim,
             int64_t num_tasks = 1, const torch::Tensor& task_metadata = {},
             std::vector<int64_t> frame_shape = {});
  // A copy would share the networks (module holders are shared pointers).
  SacLearner(const SacLearner&) = delete;
  SacLearner& operator=(const SacLearner&) = delete;
  SacLearner(SacLearner&&) = default;
  SacLearner& operator=(SacLearner&&) = default;

  // One update on a batch (any size). Throws Error on a malformed batch, or
  // if the critic loss exceeds config.max_critic_loss (before any step).
  Metrics Update(const Batch& batch) override;

  // Actions in (-1, 1) for obs (B, obs_dim) of tasks task_index (B) int64
  // in [0, num_tasks), or obs (obs_dim) with a one-element task_index
  // (gives (action_dim)): sampled, or tanh(mean) when deterministic. Runs
  // under InferenceMode; the result is an inference tensor (copy it out, do
  // not feed it to autograd). Throws Error on bad shapes or task indices.
  torch::Tensor Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                    bool deterministic);
  // Single-task form (task 0); throws Error when num_tasks > 1.
  torch::Tensor Act(const torch::Tensor& obs, bool deterministic);
  // The Actor form (no log-probabilities; SAC's actions lie in (-1, 1)). On
  // held-out tasks (state.held_out_tasks) the task_encoder architecture
  // reads the mean of the trained task encodings for every row, as MTRL's
  // HiP-BMDP evaluates its interpolation and extrapolation envs (mean_train);
  // the other architectures read task_index as a training task's.
  ActOutput Act(const torch::Tensor& obs, const torch::Tensor& task_index, ActorState& state,
                ActMode mode) override;
  Actor& AsActor() override { return *this; }

  // GradNorm's per-task weights of the critic (or actor) loss, (T); undefined
  // without config.gradnorm.
  const torch::Tensor& gradnorm_weights(bool critic) const {
    return critic ? gradnorm_critic_.weights : gradnorm_actor_.weights;
  }

  // Regularises towards `prior` from the next update on (see the top).
  void SetPrior(PolicyPrior prior) { prior_ = std::move(prior); }

  // The critic target y (B) of step 1, drawing a' from this learner's
  // generator. Exposed for tests and diagnostics.
  torch::Tensor CriticTarget(const Batch& batch);

  // The task-conditioned network input x(obs, task) (B, input_dim()) built
  // with the online (or, for "moe", the target) encoders. Differentiable in
  // the encoders when grad mode is on. Exposed for tests.
  torch::Tensor NetworkInput(const torch::Tensor& obs, const torch::Tensor& task_index,
                             bool target = false) const;
  // Shards an update is split into (config.update_shards, at most B) and
  // the threads that run them.
  int64_t update_shards() const { return config_.update_shards; }
  int update_threads() const { return pool_->num_threads(); }
  // Width of NetworkInput: obs_dim (+ num_tasks for "mlp" with several
  // tasks, + task_embedding_dim for "task_encoder"), encoder_dim +
  // task_embedding_dim for "moe".
  int64_t input_dim() const { return input_dim_; }
  // What the networks read of a batch: its frames with a pixel encoder, else
  // its observations (next: of next_obs).
  const torch::Tensor& Observation(const Batch& batch, bool next) const;
  const std::vector<int64_t>& frame_shape() const { return frame_shape_; }
  int64_t pixel_size() const;
  // Empty holders unless frame_shape was given: the pixel encoder the critic
  // loss trains, its target copy.
  nn::PixelEncoder& pixel_encoder() { return pixel_encoder_; }
  const nn::PixelEncoder& pixel_encoder() const { return pixel_encoder_; }
  nn::PixelEncoder& pixel_encoder_target() { return pixel_encoder_target_; }

  // Temperatures exp(log_alpha): (num_tasks) if disentangled, else (1).
  torch::Tensor Alpha() const { return log_alpha_.exp(); }
  double target_entropy() const { return target_entropy_; }
  int64_t num_updates() const { return num_updates_; }
  const SacConfig& config() const { return config_; }
  int64_t obs_dim() const { return obs_dim_; }
  int64_t action_dim() const { return action_dim_; }
  int64_t num_tasks() const { return num_tasks_; }

  nn::GaussianPolicy& actor() { return actor_; }
  nn::TwinCritic& critic() { return critic_; }
  // Empty holders (nullptr) unless the architecture uses them: the task
  // encoder for "task_encoder" and "moe", the mixture encoder and its target
  // copy for "moe".
  nn::TaskEncoder& task_encoder() { return task_encoder_; }
  const nn::TaskEncoder& task_encoder() const { return task_encoder_; }
  nn::MixtureEncoder& encoder() { return encoder_; }
  nn::MixtureEncoder& encoder_target() { return encoder_target_; }
  // Drives initialisation, every sampled action and the PCGrad orders.
  at::Generator& generator() { return generator_; }

  // Full training state: networks, encoders, targets, temperatures,
  // optimizers, update count, generator. Load throws Error on a checkpoint
  // of another architecture, task count or size.
  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive) override;

 private:
  // The checkpoint's networks and optimizers in Save's order; Load reads the
  // same list (Self is const for Save).
  template <typename Archive, typename Self>
  static void TransferNetworks(Archive& archive, Self& self);

  // kTaskTrunk: soft_modular, paco, moore (nn/task_trunks.h).
  enum class Arch { kMlp, kMultiHead, kTaskEncoder, kMoe, kTaskTrunk };

  // What the critic loss trains: the online critics, then the encoders the
  // architecture has, each with its optimizer. Built on demand (a moved
  // learner must not keep pointers into its old self).
  std::vector<std::pair<nn::FlatModule*, nn::FlatAdam*>> CriticGroup();
  // The parameter lists one shard computes with: shard 0 uses the modules'
  // own parameters, shard s > 0 the replicas in replicas_[s - 1].
  struct ShardParams {
    at::ArrayRef<torch::Tensor> actor, critic, task_encoder, encoder, pixel_encoder;
  };
  struct ShardReplicas {
    nn::GradientReplica actor, critic, task_encoder, encoder, pixel_encoder;
  };
  ShardParams ParamsOf(int shard) const;
  // Zeroes the gradients shard `shard` accumulates into for the critic
  // group (critic and encoders) or the actor.
  void ZeroShardGrads(int shard, bool critic_group);
  // Adds the replicas' gradients into the modules' flat gradients, in
  // shard order.
  void ReduceShardGrads(int shards, bool critic_group);
  // mean_task: every row reads the mean of the task encodings (task_encoder;
  // held-out tasks).
  torch::Tensor NetworkInputWith(const torch::Tensor& obs, const torch::Tensor& task_index,
                                 bool target, const ShardParams& params,
                                 bool mean_task = false) const;
  torch::Tensor ActOn(const torch::Tensor& obs, const torch::Tensor& task_index,
                      bool deterministic, bool mean_task);
  // Per-sample temperatures (B), or (1) when shared.
  torch::Tensor SampleAlpha(const torch::Tensor& task_index) const;
  // Per-sample loss weights (B): task_reweight's, times 0 for masked tasks,
  // times per-task weights (T) when defined (GradNorm's); undefined when
  // every weight is 1.
  torch::Tensor SampleWeights(const torch::Tensor& task_index, const torch::Tensor& masked,
                              const torch::Tensor& task_weights = {}) const;
  // PaCo: tasks (int64) whose mean critic loss over their samples exceeds
  // the threshold, from per-sample losses (B).
  torch::Tensor ExtremeTasks(const torch::Tensor& per_sample_loss,
                             const torch::Tensor& task_index) const;
  // PaCo: the task weights of `tasks` in the online actor and critics become
  // random convex combinations of the other tasks' weights.
  void ResetTaskWeights(const torch::Tensor& tasks);
  // The critic target with the given temperatures and the noise eps (B, A)
  // for the next actions.
  torch::Tensor CriticTargetWith(const Batch& batch, const torch::Tensor& alpha,
                                 const torch::Tensor& eps) const;
  // The task index for multi-head outputs, undefined otherwise.
  torch::Tensor Heads(const torch::Tensor& task_index) const;
  // Per-task gradients of `per_sample` (B) over the modules' flat buffers,
  // combined by PCGrad into their flat gradients. Returns the conflict
  // fraction.
  double PcGradBackward(const torch::Tensor& per_sample, const torch::Tensor& task_index,
                        const std::vector<nn::FlatModule*>& modules);

  SacConfig config_;
  Arch arch_;
  int64_t arch_code_;  // place in SacArchitectures(), stored in checkpoints
  int64_t obs_dim_;
  int64_t action_dim_;
  int64_t num_tasks_;
  int64_t input_dim_;
  std::vector<int64_t> frame_shape_;
  double target_entropy_;
  at::Generator generator_;
  nn::GaussianPolicy actor_{nullptr};
  nn::TwinCritic critic_{nullptr};
  nn::TaskEncoder task_encoder_{nullptr};
  nn::MixtureEncoder encoder_{nullptr};
  nn::MixtureEncoder encoder_target_{nullptr};
  nn::PixelEncoder pixel_encoder_{nullptr};
  nn::PixelEncoder pixel_encoder_target_{nullptr};
  torch::Tensor log_alpha_;  // (num_tasks) or (1)
  nn::FlatAdam actor_optimizer_;
  nn::FlatAdam critic_optimizer_;
  nn::FlatAdam alpha_optimizer_;
  nn::FlatAdam task_encoder_optimizer_;
  nn::FlatAdam encoder_optimizer_;
  nn::FlatAdam pixel_encoder_optimizer_;
  int64_t num_updates_ = 0;
  PolicyPrior prior_;
  nn::GradNormState gradnorm_critic_, gradnorm_actor_;  // GradNorm: off unless config.gradnorm
  std::vector<ShardReplicas> replicas_;  // one per shard after the first
  std::unique_ptr<nn::WorkerPool> pool_;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_SAC_SAC_H_
