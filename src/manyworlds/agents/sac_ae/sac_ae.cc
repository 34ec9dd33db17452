#include "manyworlds/agents/sac_ae/sac_ae.h"

#include <cmath>
#include <string>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/pcgrad.h"

namespace manyworlds::agents {

SacAeConfig::SacAeConfig() {
  // MTRL's DeepMind Control setup (sac_ae.h lists the files)
  hidden_dim = 1024;
  num_layers = 2;
  actor_lr = 1e-3;
  critic_lr = 1e-3;
  alpha_lr = 1e-4;
  init_temperature = 0.1;
  log_std_min = -10.0;
  actor_update_freq = 2;
  critic_target_update_freq = 2;
  tau = 0.01;
  encoder_tau = 0.05;
}

void SacAeConfig::Validate() const {
  SacConfig::Validate();
  RequireField(FinitePositive(encoder_lr), "encoder_lr", "finite and > 0", encoder_lr);
  RequireField(FinitePositive(decoder_lr), "decoder_lr", "finite and > 0", decoder_lr);
  RequireField(std::isfinite(decoder_weight_decay) && decoder_weight_decay >= 0,
               "decoder_weight_decay", "finite and >= 0", decoder_weight_decay);
  RequireField(std::isfinite(decoder_latent_lambda) && decoder_latent_lambda >= 0,
               "decoder_latent_lambda", "finite and >= 0", decoder_latent_lambda);
  RequireField(decoder_update_freq >= 1 && decoder_update_freq <= 1000000, "decoder_update_freq",
               "in [1, 1000000]", decoder_update_freq);
}

double AuxiliaryBackward(SacLearner& sac, const torch::Tensor& per_sample,
                         const torch::Tensor& task_index,
                         const std::vector<nn::FlatModule*>& modules,
                         nn::GradNormState& gradnorm,
                         const std::vector<torch::Tensor>& last_layers) {
  const SacConfig& config = sac.config();
  if (config.pcgrad) {
    return nn::PcGradBackward(per_sample, task_index, sac.num_tasks(), modules, sac.generator())
        .conflict_fraction();
  }
  if (!config.gradnorm) {
    per_sample.mean().backward();
    return 0.0;
  }
  const auto [losses, norms] =
      nn::TaskLossesAndGradNorms(per_sample, task_index, sac.num_tasks(), last_layers);
  (per_sample * gradnorm.weights.index_select(0, task_index)).mean().backward();
  const torch::Tensor present = torch::bincount(task_index, {}, sac.num_tasks()) > 0;
  return gradnorm.Step(losses, norms, present, config.gradnorm_alpha);
}

SacAeLearner::SacAeLearner(const SacAeConfig& config, int64_t obs_dim, int64_t action_dim,
                           int64_t num_tasks, const std::vector<int64_t>& frame_shape)
    : config_(Validated(config)),
      sac_(config, obs_dim, action_dim, num_tasks, {}, RequireFrameShape(frame_shape, "SAC-AE")),
      encoder_optimizer_(sac_.pixel_encoder()->num_params(),
                         SacAdamOptions(config, config.encoder_lr)),
      decoder_optimizer_(0, SacAdamOptions(config, config.decoder_lr)) {
  decoder_ = nn::PixelDecoder(SacPixelEncoderOptions(config, frame_shape),
                              config.encoder_feature_dim, sac_.generator());
  decoder_optimizer_ =
      nn::FlatAdam(decoder_->num_params(),
                   SacAdamOptions(config, config.decoder_lr, config.decoder_weight_decay));
  if (config.gradnorm) {
    gradnorm_ = nn::GradNormState(num_tasks, SacAdamOptions(config, config.gradnorm_lr));
  }
}

torch::Tensor SacAeLearner::AutoencoderLoss(const Batch& batch, at::Generator& generator) {
  nn::PixelEncoder& encoder = sac_.pixel_encoder();
  const torch::Tensor h = encoder->Forward(batch.pixels, encoder->params());
  const torch::Tensor reconstruction = decoder_->Forward(h, decoder_->params());
  const torch::Tensor target =
      nn::PreprocessFrames(batch.pixels, generator).reshape(reconstruction.sizes());
  return (reconstruction - target).square().flatten(1).mean(1) +
         config_.decoder_latent_lambda * 0.5 * h.square().sum(1);
}

Metrics SacAeLearner::Update(const Batch& batch) {
  // SAC validates the batch (frames included) before any step
  const int64_t update = sac_.num_updates();
  Metrics metrics = sac_.Update(batch);
  if (update % config_.decoder_update_freq != 0) return metrics;
  nn::PixelEncoder& encoder = sac_.pixel_encoder();
  encoder->ZeroGrad();
  decoder_->ZeroGrad();
  const torch::Tensor per_sample = AutoencoderLoss(batch, sac_.generator());
  const auto& decoder_params = decoder_->params();
  const double combined =
      AuxiliaryBackward(sac_, per_sample, batch.task_index, {encoder.get(), decoder_.get()},
                        gradnorm_, {decoder_params[decoder_params.size() - 2]});
  if (config_.pcgrad) metrics.Set("pcgrad_ae_conflicts", combined);
  if (config_.gradnorm) metrics.Set("gradnorm_ae_loss", combined);
  encoder_optimizer_.Step(encoder->flat(), encoder->flat_grad());
  decoder_optimizer_.Step(decoder_->flat(), decoder_->flat_grad());
  metrics.Set("ae_loss", per_sample.mean().item<double>());
  return metrics;
}

void SacAeLearner::Save(torch::serialize::OutputArchive& archive) const {
  sac_.Save(archive);
  Transfer(archive, "decoder", *decoder_);
  Transfer(archive, "ae_encoder_optimizer", encoder_optimizer_);
  Transfer(archive, "decoder_optimizer", decoder_optimizer_);
  if (config_.gradnorm) Transfer(archive, "gradnorm_ae", gradnorm_);
}

void SacAeLearner::Load(torch::serialize::InputArchive& archive) {
  sac_.Load(archive);
  Transfer(archive, "decoder", *decoder_);
  Transfer(archive, "ae_encoder_optimizer", encoder_optimizer_);
  Transfer(archive, "decoder_optimizer", decoder_optimizer_);
  if (config_.gradnorm) Transfer(archive, "gradnorm_ae", gradnorm_);
}

}  // namespace manyworlds::agents
