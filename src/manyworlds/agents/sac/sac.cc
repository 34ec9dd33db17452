#include "manyworlds/agents/sac/sac.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/gradnorm.h"
#include "manyworlds/nn/paco.h"
#include "manyworlds/nn/pcgrad.h"
#include "manyworlds/nn/task_trunks.h"
#include "manyworlds/nn/task_conditioning.h"
#include "manyworlds/nn/threads.h"

namespace manyworlds::agents {
namespace {

int64_t ArchCode(const std::string& architecture) {
  const std::vector<std::string>& names = SacArchitectures();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == architecture) return static_cast<int64_t>(i);
  }
  throw ConfigError("SacConfig.architecture: unknown '" + architecture + "'");
}

// Throws Error unless task_index is a (B) int64 tensor with values in [0, n).
void CheckTaskIndex(const torch::Tensor& task_index, int64_t b, int64_t n, const char* what) {
  if (!task_index.defined() || task_index.dim() != 1 || task_index.size(0) != b ||
      task_index.scalar_type() != torch::kInt64) {
    throw Error(std::string(what) + ": task_index must be an int64 tensor of shape (" +
                std::to_string(b) + ")");
  }
  auto [lo, hi] = torch::aminmax(task_index);
  if (lo.item<int64_t>() < 0 || hi.item<int64_t>() >= n) {
    throw Error(std::string(what) + ": task indices must lie in [0, " + std::to_string(n) +
                "), got [" + std::to_string(lo.item<int64_t>()) + ", " +
                std::to_string(hi.item<int64_t>()) + "]");
  }
}

// Rows [lo, lo + n) of every field.
Batch Rows(const Batch& batch, int64_t lo, int64_t n) {
  Batch part;
  part.obs = batch.obs.narrow(0, lo, n);
  part.action = batch.action.narrow(0, lo, n);
  part.reward = batch.reward.narrow(0, lo, n);
  part.next_obs = batch.next_obs.narrow(0, lo, n);
  part.done = batch.done.narrow(0, lo, n);
  part.task_index = batch.task_index.narrow(0, lo, n);
  if (batch.pixels.defined()) {
    part.pixels = batch.pixels.narrow(0, lo, n);
    part.next_pixels = batch.next_pixels.narrow(0, lo, n);
  }
  return part;
}

// Rows of a per-sample (B) tensor; a shared (1) value as it is.
torch::Tensor RowsOf(const torch::Tensor& t, int64_t lo, int64_t n, int64_t b) {
  return t.size(0) == b ? t.narrow(0, lo, n) : t;
}

int PoolThreads(const SacConfig& config, int64_t shards) {
  int64_t threads = config.update_threads;
  if (threads == 0) {
    threads = std::max<int64_t>(1, static_cast<int64_t>(std::thread::hardware_concurrency()));
  }
  return static_cast<int>(std::min(threads, shards));
}

// A fixed-size tensor of a checkpoint (the temperatures):
// written as it is; read into place, Error on another number of `what`.
void TransferTensor(torch::serialize::OutputArchive& archive, const char* key,
                    const torch::Tensor& t, const char* /*what*/ = "values") {
  archive.write(key, t);
}

void TransferTensor(torch::serialize::InputArchive& archive, const char* key,
                    const torch::Tensor& t, const char* what = "values") {
  torch::Tensor saved;
  archive.read(key, saved);
  if (saved.numel() != t.numel()) {
    throw Error("SacLearner::Load: checkpoint has " + std::to_string(saved.numel()) + " " +
                what + ", this learner " + std::to_string(t.numel()));
  }
  t.copy_(saved.reshape(t.sizes()));
}

}  // namespace

nn::AdamOptions SacAdamOptions(const SacConfig& config, double lr, double weight_decay) {
  nn::AdamOptions options;
  options.lr = lr;
  options.beta1 = config.adam_beta1;
  options.beta2 = config.adam_beta2;
  options.weight_decay = weight_decay;
  return options;
}

nn::PixelEncoderOptions SacPixelEncoderOptions(const SacConfig& config,
                                               const std::vector<int64_t>& frame_shape) {
  nn::PixelEncoderOptions options;
  options.frame_shape = frame_shape;
  options.num_layers = config.num_conv_layers;
  options.num_filters = config.num_filters;
  options.feature_dim = config.encoder_feature_dim;
  return options;
}

const std::vector<int64_t>& RequireFrameShape(const std::vector<int64_t>& frame_shape,
                                              const char* learner) {
  if (frame_shape.empty()) {
    throw ConfigError(std::string(learner) + " learns from pixel frames: give it the frame shape "
                      "(the envs need obs=pixels)");
  }
  return frame_shape;
}

torch::Tensor SoftTdTarget(const torch::Tensor& reward, const torch::Tensor& done,
                           const torch::Tensor& next_q, const torch::Tensor& next_log_prob,
                           const torch::Tensor& alpha, double discount) {
  torch::Tensor not_done = 1.0 - done.to(reward.scalar_type());
  return reward + discount * not_done * (next_q - alpha * next_log_prob);
}

SacLearner::SacLearner(const SacConfig& config, int64_t obs_dim, int64_t action_dim,
                       int64_t num_tasks, const torch::Tensor& task_metadata,
                       std::vector<int64_t> frame_shape)
    : config_(Validated(config)),
      arch_(static_cast<Arch>(std::min<int64_t>(ArchCode(config.architecture),
                                                static_cast<int64_t>(Arch::kTaskTrunk)))),
      arch_code_(ArchCode(config.architecture)),
      obs_dim_(obs_dim),
      action_dim_(action_dim),
      num_tasks_(num_tasks),
      input_dim_(obs_dim),
      frame_shape_(std::move(frame_shape)),
      target_entropy_(config.target_entropy.value_or(-static_cast<double>(action_dim))),
      generator_(at::detail::createCPUGenerator(config.seed)),
      actor_optimizer_(0, SacAdamOptions(config, config.actor_lr)),
      critic_optimizer_(0, SacAdamOptions(config, config.critic_lr)),
      alpha_optimizer_(0, SacAdamOptions(config, config.alpha_lr)),
      task_encoder_optimizer_(0, SacAdamOptions(config, config.actor_lr)),
      encoder_optimizer_(0, SacAdamOptions(config, config.critic_lr)),
      pixel_encoder_optimizer_(0, SacAdamOptions(config, config.critic_lr)) {
  if (obs_dim <= 0 || action_dim <= 0 || num_tasks <= 0) {
    throw ConfigError("SacLearner: obs_dim, action_dim and num_tasks must be > 0, got " +
                      std::to_string(obs_dim) + ", " + std::to_string(action_dim) + ", " +
                      std::to_string(num_tasks));
  }
  // PCGrad and GradNorm need every task's loss on one graph: one shard.
  const int64_t shards = config.pcgrad || config.gradnorm ? 1 : config.update_shards;
  const int threads = PoolThreads(config, shards);
  nn::ConfigureTorchThreads(/*own_threads=*/threads > 1);

  // Encoders first (fixed order of draws from the generator: pixel encoder,
  // task encoder, mixture encoder, actor, critics).
  if (!frame_shape_.empty()) {
    const nn::PixelEncoderOptions pixels = SacPixelEncoderOptions(config, frame_shape_);
    pixel_encoder_ = nn::PixelEncoder(pixels, generator_);
    pixel_encoder_target_ = nn::PixelEncoder(pixels, generator_);
    pixel_encoder_target_->CopyFrom(*pixel_encoder_);
    for (const torch::Tensor& p : pixel_encoder_target_->params()) p.requires_grad_(false);
    pixel_encoder_optimizer_ =
        nn::FlatAdam(pixel_encoder_->num_params(), SacAdamOptions(config, config.critic_lr));
    // the features are the observation from here on
    obs_dim = config.encoder_feature_dim;
    input_dim_ = obs_dim;
  }
  const int64_t embed = config.task_embedding_dim;
  if (config.task_metadata.empty() != !task_metadata.defined()) {
    throw ConfigError(config.task_metadata.empty()
                          ? "SacLearner: task vectors given, but agent.task_metadata is empty"
                          : "SacLearner: agent.task_metadata is set, but no task vectors were "
                            "read from it");
  }
  if (arch_ == Arch::kTaskEncoder || arch_ == Arch::kMoe) {
    nn::TaskEncoderOptions encoder = nn::ConditioningTaskEncoderOptions(num_tasks, embed);
    if (config.task_encoder_hidden > 0) encoder.hidden_dim = config.task_encoder_hidden;
    encoder.num_layers = config.task_encoder_layers;
    encoder.pretrained = task_metadata;
    task_encoder_ = nn::TaskEncoder(encoder, generator_);
    task_encoder_optimizer_ =
        nn::FlatAdam(task_encoder_->num_params(), SacAdamOptions(config, config.actor_lr));
  }
  int64_t heads = 1;
  switch (arch_) {
    case Arch::kMlp:
      if (num_tasks > 1) input_dim_ = obs_dim + num_tasks;
      break;
    case Arch::kMultiHead:
      heads = num_tasks;
      break;
    case Arch::kTaskEncoder:
      input_dim_ = obs_dim + embed;
      break;
    case Arch::kMoe: {
      const nn::MixtureEncoderOptions moe =
          nn::ConditioningMixtureOptions(obs_dim, embed, config.encoder_dim, config.num_experts);
      encoder_ = nn::MixtureEncoder(moe, generator_);
      encoder_target_ = nn::MixtureEncoder(moe, generator_);
      encoder_target_->CopyFrom(*encoder_);
      for (const torch::Tensor& p : encoder_target_->params()) p.requires_grad_(false);
      encoder_optimizer_ = nn::FlatAdam(encoder_->num_params(), SacAdamOptions(config, config.critic_lr));
      input_dim_ = config.encoder_dim + embed;
      break;
    }
    case Arch::kTaskTrunk:
      break;
  }

  nn::GaussianPolicyOptions actor;
  actor.obs_dim = input_dim_;
  actor.action_dim = action_dim;
  actor.hidden_dim = config.hidden_dim;
  actor.num_layers = config.num_layers;
  actor.log_std_min = config.log_std_min;
  actor.log_std_max = config.log_std_max;
  actor.num_heads = heads;
  nn::TaskTrunkOptions trunk;
  if (arch_ == Arch::kTaskTrunk) {
    trunk.num_tasks = num_tasks;
    trunk.hidden_dim = config.hidden_dim;
    trunk.num_layers = config.num_layers;
    trunk.num_experts = config.num_experts;
    trunk.num_param_sets = config.num_param_sets;
    trunk.num_modules = config.num_modules;
    trunk.module_layers = config.module_layers;
    trunk.module_hidden = config.module_hidden;
    trunk.routing_layers = config.routing_layers;
    trunk.routing_hidden = config.routing_hidden;
    trunk.input_dim = input_dim_;
    trunk.output_dim = 2 * action_dim;
    actor_ = nn::GaussianPolicy(actor, nn::TaskTrunkFactory(config.architecture, trunk),
                                trunk.output_dim, generator_);
  } else {
    actor_ = nn::GaussianPolicy(actor, generator_);
  }

  nn::TwinCriticOptions critic;
  critic.obs_dim = input_dim_;
  critic.action_dim = action_dim;
  critic.hidden_dim = config.hidden_dim;
  critic.num_layers = config.num_layers;
  critic.num_heads = heads;
  if (arch_ == Arch::kTaskTrunk) {
    trunk.input_dim = input_dim_ + action_dim;
    trunk.output_dim = 1;
    trunk.ensemble_size = 2;
    critic_ = nn::TwinCritic(critic, nn::TaskTrunkFactory(config.architecture, trunk), generator_);
  } else {
    critic_ = nn::TwinCritic(critic, generator_);
  }

  log_alpha_ = torch::full({config.disentangled_alpha ? num_tasks : 1},
                           std::log(config.init_temperature), torch::kFloat32);
  actor_optimizer_ = nn::FlatAdam(actor_->trunk()->num_params(), SacAdamOptions(config, config.actor_lr));
  critic_optimizer_ =
      nn::FlatAdam(critic_->online()->num_params(), SacAdamOptions(config, config.critic_lr));
  alpha_optimizer_ = nn::FlatAdam(log_alpha_.numel(), SacAdamOptions(config, config.alpha_lr));
  if (config.gradnorm) {
    gradnorm_critic_ = nn::GradNormState(num_tasks, SacAdamOptions(config, config.gradnorm_lr));
    gradnorm_actor_ = nn::GradNormState(num_tasks, SacAdamOptions(config, config.gradnorm_lr));
  }

  for (int64_t s = 1; s < shards; ++s) {
    ShardReplicas r;
    r.actor = actor_->trunk()->MakeGradientReplica();
    r.critic = critic_->online()->MakeGradientReplica();
    if (task_encoder_) r.task_encoder = task_encoder_->MakeGradientReplica();
    if (encoder_) r.encoder = encoder_->MakeGradientReplica();
    if (pixel_encoder_) r.pixel_encoder = pixel_encoder_->MakeGradientReplica();
    replicas_.push_back(std::move(r));
  }
  pool_ = std::make_unique<nn::WorkerPool>(threads);
}

SacLearner::ShardParams SacLearner::ParamsOf(int shard) const {
  if (shard == 0) {
    ShardParams p;
    p.actor = actor_->trunk()->params();
    p.critic = critic_->online()->params();
    if (task_encoder_) p.task_encoder = task_encoder_->params();
    if (encoder_) p.encoder = encoder_->params();
    if (pixel_encoder_) p.pixel_encoder = pixel_encoder_->params();
    return p;
  }
  const ShardReplicas& r = replicas_[static_cast<size_t>(shard - 1)];
  return {r.actor.params, r.critic.params, r.task_encoder.params, r.encoder.params,
          r.pixel_encoder.params};
}

void SacLearner::ZeroShardGrads(int shard, bool critic_group) {
  if (shard == 0) {
    if (!critic_group) {
      actor_->trunk()->ZeroGrad();
      return;
    }
    for (const auto& [module, optimizer] : CriticGroup()) module->ZeroGrad();
    return;
  }
  ShardReplicas& r = replicas_[static_cast<size_t>(shard - 1)];
  if (!critic_group) {
    r.actor.ZeroGrad();
    return;
  }
  r.critic.ZeroGrad();
  if (task_encoder_) r.task_encoder.ZeroGrad();
  if (encoder_) r.encoder.ZeroGrad();
  if (pixel_encoder_) r.pixel_encoder.ZeroGrad();
}

void SacLearner::ReduceShardGrads(int shards, bool critic_group) {
  for (int s = 1; s < shards; ++s) {
    const ShardReplicas& r = replicas_[static_cast<size_t>(s - 1)];
    if (!critic_group) {
      actor_->trunk()->flat_grad().add_(r.actor.flat_grad);
      continue;
    }
    critic_->online()->flat_grad().add_(r.critic.flat_grad);
    if (task_encoder_) task_encoder_->flat_grad().add_(r.task_encoder.flat_grad);
    if (encoder_) encoder_->flat_grad().add_(r.encoder.flat_grad);
    if (pixel_encoder_) pixel_encoder_->flat_grad().add_(r.pixel_encoder.flat_grad);
  }
}

std::vector<std::pair<nn::FlatModule*, nn::FlatAdam*>> SacLearner::CriticGroup() {
  std::vector<std::pair<nn::FlatModule*, nn::FlatAdam*>> group = {
      {critic_->online().get(), &critic_optimizer_}};
  if (encoder_) group.emplace_back(encoder_.get(), &encoder_optimizer_);
  if (task_encoder_ && config_.critic_trains_task_encoder) {
    group.emplace_back(task_encoder_.get(), &task_encoder_optimizer_);
  }
  if (pixel_encoder_) group.emplace_back(pixel_encoder_.get(), &pixel_encoder_optimizer_);
  return group;
}

const torch::Tensor& SacLearner::Observation(const Batch& batch, bool next) const {
  if (pixel_encoder_) return next ? batch.next_pixels : batch.pixels;
  return next ? batch.next_obs : batch.obs;
}

int64_t SacLearner::pixel_size() const {
  int64_t n = frame_shape_.empty() ? 0 : 1;
  for (const int64_t d : frame_shape_) n *= d;
  return n;
}

torch::Tensor SacLearner::NetworkInput(const torch::Tensor& obs, const torch::Tensor& task_index,
                                       bool target) const {
  return NetworkInputWith(obs, task_index, target, ParamsOf(0));
}

torch::Tensor SacLearner::NetworkInputWith(const torch::Tensor& observation,
                                           const torch::Tensor& task_index, bool target,
                                           const ShardParams& params, bool mean_task) const {
  // frames: the encoder's features are the observation (the target critics read the target
  // encoder's)
  const torch::Tensor obs =
      !pixel_encoder_ ? observation
      : target        ? pixel_encoder_target_->Forward(observation,
                                                       pixel_encoder_target_->detached_params())
                      : pixel_encoder_->Forward(observation, params.pixel_encoder);
  switch (arch_) {
    case Arch::kMlp:
      if (num_tasks_ == 1) return obs;
      return torch::cat({obs, torch::one_hot(task_index, num_tasks_).to(obs.scalar_type())}, -1);
    case Arch::kMultiHead:
    case Arch::kTaskTrunk:
      return obs;
    case Arch::kTaskEncoder: {
      const torch::Tensor z = config_.critic_trains_task_encoder
                                  ? task_encoder_->Encode(params.task_encoder)
                                  : task_encoder_->Encode(task_encoder_->detached_params());
      if (mean_task) return torch::cat({obs, z.mean(0, true).expand({obs.size(0), -1})}, -1);
      return torch::cat({obs, z.index_select(0, task_index)}, -1);
    }
    case Arch::kMoe: {
      // All task encodings (num_tasks, E) and mixture weights (num_tasks, K)
      // are tiny; rows are picked per sample. The selector reads the task
      // encoding detached (MTRL's should_detach_task_encoding).
      const torch::Tensor z = task_encoder_->Encode(params.task_encoder);
      const nn::MixtureEncoder& moe = target ? encoder_target_ : encoder_;
      const at::ArrayRef<torch::Tensor> weights_params =
          target ? at::ArrayRef<torch::Tensor>(moe->detached_params()) : params.encoder;
      const torch::Tensor weights =
          moe->Weights(z.detach(), weights_params).index_select(0, task_index);
      return torch::cat({moe->Mix(obs, weights, weights_params), z.index_select(0, task_index)},
                        -1);
    }
  }
  throw Error("SacLearner: unknown architecture");
}

torch::Tensor SacLearner::Heads(const torch::Tensor& task_index) const {
  return arch_ == Arch::kMultiHead || arch_ == Arch::kTaskTrunk ? task_index : torch::Tensor();
}

torch::Tensor SacLearner::SampleAlpha(const torch::Tensor& task_index) const {
  torch::Tensor alpha = log_alpha_.exp();
  return config_.disentangled_alpha ? alpha.index_select(0, task_index) : alpha;
}

torch::Tensor SacLearner::SampleWeights(const torch::Tensor& task_index,
                                        const torch::Tensor& masked,
                                        const torch::Tensor& task_weights) const {
  const bool any_masked = masked.defined() && masked.numel() > 0;
  if (!config_.task_reweight && !any_masked && !task_weights.defined()) return {};
  torch::NoGradGuard no_grad;
  // Per-task weights (T): T softmax(-log alpha), or ones; masked tasks 0.
  torch::Tensor per_task =
      config_.task_reweight
          ? static_cast<double>(num_tasks_) * torch::softmax(-log_alpha_, 0)
          : torch::ones({num_tasks_}, torch::kFloat32);
  if (task_weights.defined()) per_task = per_task * task_weights;
  if (any_masked) per_task = per_task.index_fill(0, masked, 0.0);
  return per_task.index_select(0, task_index);
}

torch::Tensor SacLearner::ExtremeTasks(const torch::Tensor& per_sample_loss,
                                       const torch::Tensor& task_index) const {
  torch::NoGradGuard no_grad;
  const torch::Tensor sums =
      torch::zeros({num_tasks_}, torch::kFloat32).index_add_(0, task_index, per_sample_loss);
  const torch::Tensor counts = torch::bincount(task_index, {}, num_tasks_).to(torch::kFloat32);
  const torch::Tensor mean = sums / counts.clamp_min(1.0);
  return torch::nonzero(mean > config_.paco_reset_threshold).reshape({-1});
}

void SacLearner::ResetTaskWeights(const torch::Tensor& tasks) {
  torch::NoGradGuard no_grad;
  torch::Tensor normal = torch::ones({num_tasks_}, torch::kBool).index_fill(0, tasks, false);
  const torch::Tensor normal_tasks = torch::nonzero(normal).reshape({-1});
  if (normal_tasks.numel() == 0) return;  // nothing to interpolate from
  for (nn::TrunkImpl* trunk : {actor_->trunk().get(), critic_->online().get()}) {
    const auto* paco = dynamic_cast<const nn::PacoTrunkImpl*>(trunk);
    if (paco == nullptr) throw Error("SacLearner: a PaCo reset needs PaCo networks");
    const torch::Tensor w = paco->task_weights();  // (E, T, K)
    // Rows of random L1-normalised mixing weights, (extreme, normal).
    torch::Tensor mix = torch::rand({tasks.numel(), normal_tasks.numel()}, generator_);
    mix = mix / mix.sum(1, true);
    for (int64_t e = 0; e < w.size(0); ++e) {
      w[e].index_copy_(0, tasks, torch::matmul(mix, w[e].index_select(0, normal_tasks)));
    }
  }
}

torch::Tensor SacLearner::CriticTargetWith(const Batch& batch, const torch::Tensor& alpha,
                                           const torch::Tensor& eps) const {
  torch::NoGradGuard no_grad;
  const torch::Tensor heads = Heads(batch.task_index);
  const torch::Tensor& next_obs = Observation(batch, /*next=*/true);
  const torch::Tensor actor_in = NetworkInput(next_obs, batch.task_index);
  const torch::Tensor critic_in =
      arch_ == Arch::kMoe || pixel_encoder_
          ? NetworkInput(next_obs, batch.task_index, /*target=*/true)
          : actor_in;
  const nn::PolicyOutput next =
      actor_->Forward(actor_in, heads, actor_->trunk()->detached_params());
  const nn::SquashedSample sample = nn::SquashedGaussianFromNoise(next.mean, next.log_std, eps);
  const torch::Tensor q = critic_->TargetQ(critic_in, sample.action, heads);  // (2, B)
  if (prior_.log_prob) {
    // min Q' - (alpha + c) log pi + c log pi_0
    return SoftTdTarget(batch.reward, batch.done,
                        torch::minimum(q[0], q[1]) +
                            prior_.weight * prior_.log_prob(batch.next_obs, sample.pre_tanh),
                        sample.log_prob, alpha + prior_.weight, config_.discount);
  }
  return SoftTdTarget(batch.reward, batch.done, torch::minimum(q[0], q[1]), sample.log_prob,
                      alpha, config_.discount);
}

torch::Tensor SacLearner::CriticTarget(const Batch& batch) {
  ValidateBatch(batch, obs_dim_, action_dim_, num_tasks_, pixel_size());
  const torch::Tensor eps =
      torch::randn({batch.size(), action_dim_}, generator_, torch::kFloat32);
  return CriticTargetWith(batch, SampleAlpha(batch.task_index), eps);
}

double SacLearner::PcGradBackward(const torch::Tensor& per_sample,
                                  const torch::Tensor& task_index,
                                  const std::vector<nn::FlatModule*>& modules) {
  return nn::PcGradBackward(per_sample, task_index, num_tasks_, modules, generator_)
      .conflict_fraction();
}

Metrics SacLearner::Update(const Batch& batch) {
  ValidateBatch(batch, obs_dim_, action_dim_, num_tasks_, pixel_size());
  Metrics metrics;
  const int64_t b = batch.size();
  const bool actor_step = num_updates_ % config_.actor_update_freq == 0;
  // Every random draw of the update, for the whole batch, before the split.
  const torch::Tensor next_eps = torch::randn({b, action_dim_}, generator_, torch::kFloat32);
  const torch::Tensor actor_eps =
      actor_step ? torch::randn({b, action_dim_}, generator_, torch::kFloat32) : torch::Tensor();
  const torch::Tensor alpha = SampleAlpha(batch.task_index);  // (B) or (1), no grad
  const int shards = static_cast<int>(std::min<int64_t>(1 + replicas_.size(), b));
  // Shard s holds rows [lo, lo + n).
  auto rows = [&](int s) {
    const int64_t lo = s * b / shards;
    return std::pair<int64_t, int64_t>(lo, (s + 1) * b / shards - lo);
  };

  // Critic (and the encoders it trains). Each shard's loss is its sum over
  // rows divided by B, so the shards add up to MSE(Q1, y) + MSE(Q2, y).
  const bool paco_resets = config_.architecture == "paco" && config_.paco_reset_threshold > 0.0;
  torch::Tensor masked;  // PaCo: tasks left out of this update
  // (B) or undefined
  torch::Tensor weights = SampleWeights(batch.task_index, masked, gradnorm_critic_.weights);
  torch::Tensor task_losses, task_norms;  // GradNorm: (T) each
  std::vector<double> critic_loss_part(shards), q_sum_part(shards);
  std::vector<torch::Tensor> sample_loss_part(shards);  // PaCo: (n) per shard
  torch::Tensor critic_per_sample;  // PCGrad (one shard): (B)
  auto critic_phase = [&] {
    pool_->Run(shards, [&](int s) {
      const auto [lo, n] = rows(s);
      const Batch part = Rows(batch, lo, n);
      const ShardParams params = ParamsOf(s);
      const torch::Tensor y =
          CriticTargetWith(part, RowsOf(alpha, lo, n, b), next_eps.narrow(0, lo, n));
      const torch::Tensor x =
          NetworkInputWith(Observation(part, false), part.task_index, false, params);
      const torch::Tensor q =
          critic_->Q(x, part.action, Heads(part.task_index), params.critic);  // (2, n)
      const torch::Tensor squared = (q - y).square();
      torch::Tensor per_sample;  // (n), only where needed: the plain loss sums (2, n) directly
      if (config_.pcgrad || weights.defined() || paco_resets) per_sample = squared.sum(0);
      if (paco_resets) sample_loss_part[s] = per_sample.detach();
      if (config_.gradnorm) {  // one shard: rows are the batch
        std::tie(task_losses, task_norms) = nn::TaskLossesAndGradNorms(
            per_sample, part.task_index, num_tasks_, {params.critic[params.critic.size() - 2]});
      }
      if (weights.defined()) per_sample = per_sample * weights.narrow(0, lo, n);
      const torch::Tensor loss =
          (weights.defined() ? per_sample.sum() : squared.sum()) / static_cast<double>(b);
      critic_loss_part[s] = loss.item<double>();
      q_sum_part[s] = q.detach().sum().item<double>();
      if (config_.pcgrad) {
        critic_per_sample = per_sample;
        return;
      }
      ZeroShardGrads(s, /*critic_group=*/true);
      loss.backward();
    });
  };
  critic_phase();
  if (paco_resets) {
    const torch::Tensor extreme = ExtremeTasks(
        shards == 1 ? sample_loss_part[0] : torch::cat(sample_loss_part), batch.task_index);
    if (extreme.numel() > 0) {
      // Rare: recompute the phase with those tasks' samples weighted 0.
      masked = extreme;
      weights = SampleWeights(batch.task_index, masked, gradnorm_critic_.weights);
      critic_phase();
    }
    metrics.Set("paco_resets", static_cast<double>(extreme.numel()));
  }
  double critic_loss_value = 0.0, q_sum = 0.0;
  for (int s = 0; s < shards; ++s) {
    critic_loss_value += critic_loss_part[s];
    q_sum += q_sum_part[s];
  }
  if (config_.max_critic_loss > 0.0 && !(critic_loss_value <= config_.max_critic_loss)) {
    throw Error("SAC critic loss " + std::to_string(critic_loss_value) + " exceeds " +
                "max_critic_loss " + std::to_string(config_.max_critic_loss) +
                " at update " + std::to_string(num_updates_) + " (diverged)");
  }
  const std::vector<std::pair<nn::FlatModule*, nn::FlatAdam*>> group = CriticGroup();
  if (config_.pcgrad) {
    std::vector<nn::FlatModule*> modules;
    for (const auto& [module, optimizer] : group) modules.push_back(module);
    metrics.Set("pcgrad_conflicts", PcGradBackward(critic_per_sample, batch.task_index, modules));
  } else {
    ReduceShardGrads(shards, /*critic_group=*/true);
  }
  for (const auto& [module, optimizer] : group) {
    optimizer->Step(module->flat(), module->flat_grad());
  }
  metrics.Set("critic_loss", critic_loss_value);
  metrics.Set("q_mean", q_sum / (2.0 * static_cast<double>(b)));
  torch::Tensor present;  // GradNorm: (T) bool, the tasks in this batch
  if (config_.gradnorm) {
    present = torch::bincount(batch.task_index, {}, num_tasks_) > 0;
    metrics.Set("gradnorm_loss", gradnorm_critic_.Step(task_losses, task_norms, present,
                                                       config_.gradnorm_alpha));
    metrics.Set("gradnorm_weight_min", gradnorm_critic_.weights.min().item<double>());
    metrics.Set("gradnorm_weight_max", gradnorm_critic_.weights.max().item<double>());
  }

  // Actor and temperature, against the critics (and encoders) just updated.
  if (actor_step) {
    std::vector<double> actor_loss_part(shards);
    std::vector<torch::Tensor> log_prob_part(shards);
    const torch::Tensor actor_weights =
        SampleWeights(batch.task_index, masked, gradnorm_actor_.weights);
    torch::Tensor actor_task_losses, actor_task_norms;
    torch::Tensor actor_per_sample;  // PCGrad (one shard): (B)
    pool_->Run(shards, [&](int s) {
      const auto [lo, n] = rows(s);
      const torch::Tensor obs = Observation(batch, false).narrow(0, lo, n);
      const torch::Tensor task = batch.task_index.narrow(0, lo, n);
      const torch::Tensor heads = Heads(task);
      const ShardParams params = ParamsOf(s);
      torch::Tensor x;
      {
        torch::NoGradGuard no_grad;  // the actor sees encodings detached
        x = NetworkInputWith(obs, task, false, params);
      }
      const nn::PolicyOutput out = actor_->Forward(x, heads, params.actor);
      const nn::SquashedSample pi =
          nn::SquashedGaussianFromNoise(out.mean, out.log_std, actor_eps.narrow(0, lo, n));
      // Detached critic weights: the backward reaches the action only.
      const torch::Tensor q_pi =
          critic_->Q(x, pi.action, heads, critic_->online()->detached_params());
      torch::Tensor per_sample =
          RowsOf(alpha, lo, n, b) * pi.log_prob - torch::minimum(q_pi[0], q_pi[1]);
      if (prior_.log_prob) {
        per_sample = per_sample + prior_.weight * (pi.log_prob - prior_.log_prob(obs, pi.pre_tanh));
      }
      if (config_.gradnorm) {
        std::tie(actor_task_losses, actor_task_norms) = nn::TaskLossesAndGradNorms(
            per_sample, task, num_tasks_, {params.actor[params.actor.size() - 2]});
      }
      if (actor_weights.defined()) per_sample = per_sample * actor_weights.narrow(0, lo, n);
      const torch::Tensor loss = per_sample.sum() / static_cast<double>(b);
      actor_loss_part[s] = loss.item<double>();
      log_prob_part[s] = pi.log_prob.detach();
      if (config_.pcgrad) {
        actor_per_sample = per_sample;
        return;
      }
      ZeroShardGrads(s, /*critic_group=*/false);
      loss.backward();
    });
    nn::TrunkImpl& trunk = *actor_->trunk();
    if (config_.pcgrad) {
      metrics.Set("pcgrad_actor_conflicts",
                  PcGradBackward(actor_per_sample, batch.task_index, {&trunk}));
    } else {
      ReduceShardGrads(shards, /*critic_group=*/false);
    }
    actor_optimizer_.Step(trunk.flat(), trunk.flat_grad());
    if (config_.gradnorm) {
      metrics.Set("gradnorm_actor_loss",
                  gradnorm_actor_.Step(actor_task_losses, actor_task_norms, present,
                                       config_.gradnorm_alpha));
    }
    double actor_loss_value = 0.0;
    for (double part : actor_loss_part) actor_loss_value += part;

    // d/dlog_alpha of mean_b(alpha_b (-log_prob_b - target)) is alpha_b (...)
    // summed per temperature and divided by B.
    const torch::Tensor log_prob = shards == 1 ? log_prob_part[0] : torch::cat(log_prob_part);
    const torch::Tensor per_sample_alpha = alpha * (-log_prob - target_entropy_);  // (B)
    torch::Tensor alpha_grad =
        config_.disentangled_alpha
            ? torch::zeros_like(log_alpha_).index_add_(0, batch.task_index, per_sample_alpha) / b
            : per_sample_alpha.mean().reshape({1});
    alpha_optimizer_.Step(log_alpha_, alpha_grad);

    metrics.Set("actor_loss", actor_loss_value);
    metrics.Set("alpha", alpha.mean().item<double>());
    metrics.Set("alpha_loss", per_sample_alpha.mean().item<double>());
    metrics.Set("entropy", -log_prob.mean().item<double>());
  }

  if (masked.defined() && masked.numel() > 0) ResetTaskWeights(masked);
  if (num_updates_ % config_.critic_target_update_freq == 0) {
    critic_->UpdateTarget(config_.tau);
    if (encoder_) nn::PolyakUpdate(encoder_target_->flat(), encoder_->flat(), config_.tau);
    if (pixel_encoder_) {
      nn::PolyakUpdate(pixel_encoder_target_->flat(), pixel_encoder_->flat(), config_.encoder_tau);
    }
  }
  ++num_updates_;
  return metrics;
}

torch::Tensor SacLearner::Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                              bool deterministic) {
  return ActOn(obs, task_index, deterministic, /*mean_task=*/false);
}

torch::Tensor SacLearner::ActOn(const torch::Tensor& obs, const torch::Tensor& task_index,
                                bool deterministic, bool mean_task) {
  c10::InferenceMode inference;
  // frames (B, C, H, W) or one (C, H, W), whose size the encoder checks; else (B, obs_dim) or one
  const bool frames = static_cast<bool>(pixel_encoder_);
  const bool single = obs.dim() == (frames ? 3 : 1);
  const torch::Tensor x = single ? obs.unsqueeze(0) : obs;
  if (frames ? x.dim() != 4 : (x.dim() != 2 || x.size(1) != obs_dim_)) {
    throw Error(frames ? std::string("SacLearner::Act: this learner acts on frames (B, C, H, W) "
                                     "or (C, H, W)")
                       : "SacLearner::Act: obs must be (B, " + std::to_string(obs_dim_) +
                             ") or (" + std::to_string(obs_dim_) + ")");
  }
  const torch::Tensor task = single && task_index.defined() ? task_index.reshape({-1})
                                                            : task_index;
  CheckTaskIndex(task, x.size(0), num_tasks_, "SacLearner::Act");
  const nn::PolicyOutput out = actor_->forward(
      NetworkInputWith(frames ? x : x.to(torch::kFloat32), task, false, ParamsOf(0), mean_task),
      Heads(task));
  torch::Tensor action = deterministic
                             ? torch::tanh(out.mean)
                             : nn::SampleSquashedGaussian(out.mean, out.log_std, generator_).action;
  return single ? action.squeeze(0) : action;
}

torch::Tensor SacLearner::Act(const torch::Tensor& obs, bool deterministic) {
  if (num_tasks_ != 1) {
    throw Error("SacLearner::Act(obs, deterministic) is for single-task learners; this one has " +
                std::to_string(num_tasks_) + " tasks: call Act(obs, task_index, deterministic)");
  }
  const int64_t b = obs.dim() == (pixel_encoder_ ? 4 : 2) ? obs.size(0) : 1;
  return Act(obs, torch::zeros({b}, torch::kInt64), deterministic);
}

ActOutput SacLearner::Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                          ActorState& state, ActMode mode) {
  ActOutput out;
  out.action = ActOn(obs, task_index, mode == ActMode::kDeterministic, state.held_out_tasks);
  return out;
}

template <typename Archive, typename Self>
void SacLearner::TransferNetworks(Archive& archive, Self& self) {
  Transfer(archive, "actor", *self.actor_->trunk());
  Transfer(archive, "critic", *self.critic_->online());
  Transfer(archive, "critic_target", *self.critic_->target());
  TransferTensor(archive, "log_alpha", self.log_alpha_, "temperatures");
  Transfer(archive, "actor_optimizer", self.actor_optimizer_);
  Transfer(archive, "critic_optimizer", self.critic_optimizer_);
  Transfer(archive, "alpha_optimizer", self.alpha_optimizer_);
  if (self.task_encoder_) {
    Transfer(archive, "task_encoder", *self.task_encoder_);
    Transfer(archive, "task_encoder_optimizer", self.task_encoder_optimizer_);
  }
  if (self.encoder_) {
    Transfer(archive, "encoder", *self.encoder_);
    Transfer(archive, "encoder_target", *self.encoder_target_);
    Transfer(archive, "encoder_optimizer", self.encoder_optimizer_);
  }
  if (self.pixel_encoder_) {
    Transfer(archive, "pixel_encoder", *self.pixel_encoder_);
    Transfer(archive, "pixel_encoder_target", *self.pixel_encoder_target_);
    Transfer(archive, "pixel_encoder_optimizer", self.pixel_encoder_optimizer_);
  }
  if (self.config_.gradnorm) {
    Transfer(archive, "gradnorm_critic", self.gradnorm_critic_);
    Transfer(archive, "gradnorm_actor", self.gradnorm_actor_);
  }
}

void SacLearner::Save(torch::serialize::OutputArchive& archive) const {
  archive.write("architecture", torch::tensor(arch_code_, torch::kInt64));
  archive.write("num_tasks", torch::tensor(num_tasks_, torch::kInt64));
  if (pixel_encoder_) archive.write("frame_shape", torch::tensor(frame_shape_, torch::kInt64));
  if (task_encoder_ && task_encoder_->pretrained().defined()) {
    archive.write("task_metadata", task_encoder_->pretrained());
  }
  TransferNetworks(archive, *this);
  WriteProgress(archive, num_updates_, generator_);
}

void SacLearner::Load(torch::serialize::InputArchive& archive) {
  torch::Tensor arch, tasks;
  if (!archive.try_read("architecture", arch) || !archive.try_read("num_tasks", tasks)) {
    throw Error("SacLearner::Load: not a SAC checkpoint of this version (no architecture)");
  }
  const std::vector<std::string>& names = SacArchitectures();
  const int64_t code = arch.item<int64_t>();
  if (code != arch_code_ || tasks.item<int64_t>() != num_tasks_) {
    const std::string saved = code >= 0 && code < static_cast<int64_t>(names.size())
                                  ? names[static_cast<size_t>(code)]
                                  : "unknown";
    throw Error("SacLearner::Load: checkpoint is architecture '" + saved + "' with " +
                std::to_string(tasks.item<int64_t>()) + " tasks, this learner '" +
                config_.architecture + "' with " + std::to_string(num_tasks_));
  }
  torch::Tensor saved_frames;
  const bool has_frames = archive.try_read("frame_shape", saved_frames);
  const std::vector<int64_t> frames =
      has_frames ? std::vector<int64_t>(saved_frames.data_ptr<int64_t>(),
                                        saved_frames.data_ptr<int64_t>() + saved_frames.numel())
                 : std::vector<int64_t>();
  if (frames != frame_shape_) {
    auto describe = [](const std::vector<int64_t>& shape) {
      if (shape.empty()) return std::string("the state");
      std::string s = "frames (";
      for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
      return s + ")";
    };
    throw Error("SacLearner::Load: the checkpoint acts on " + describe(frames) +
                ", this learner on " + describe(frame_shape_) +
                " (env.options obs, pixel_width, pixel_height or frame_stack changed?)");
  }
  torch::Tensor saved_metadata;
  const bool has_metadata = archive.try_read("task_metadata", saved_metadata);
  const torch::Tensor mine =
      task_encoder_ ? task_encoder_->pretrained() : torch::Tensor();
  if (has_metadata != mine.defined() ||
      (has_metadata && (saved_metadata.sizes() != mine.sizes() ||
                        !torch::equal(saved_metadata, mine)))) {
    throw Error(std::string("SacLearner::Load: ") +
                (has_metadata && mine.defined()
                     ? "the checkpoint's task metadata vectors differ from this learner's "
                       "(agent.task_metadata changed?)"
                 : has_metadata ? "the checkpoint was trained with task metadata vectors, this "
                                  "learner has none (agent.task_metadata)"
                                : "the checkpoint was trained without task metadata, this "
                                  "learner has some (agent.task_metadata)"));
  }
  TransferNetworks(archive, *this);
  ReadProgress(archive, num_updates_, generator_);
}

}  // namespace manyworlds::agents
