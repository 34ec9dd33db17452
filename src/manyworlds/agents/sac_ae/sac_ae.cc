#include "manyworlds/agents/sac_ae/sac_ae.h"

#include <cmath>
#include <sstream>
#include <string>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"

namespace manyworlds::agents {
namespace {

template <typename T>
void Require(bool ok, const char* field, const char* allowed, T value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "SacAeConfig." << field << " must be " << allowed << ", got " << value;
  throw ConfigError(msg.str());
}

nn::AdamOptions Adam(const SacConfig& config, double lr, double weight_decay = 0.0) {
  nn::AdamOptions options;
  options.lr = lr;
  options.beta1 = config.adam_beta1;
  options.beta2 = config.adam_beta2;
  options.weight_decay = weight_decay;
  return options;
}

nn::PixelEncoderOptions EncoderOptions(const SacConfig& config,
                                       const std::vector<int64_t>& frame_shape) {
  nn::PixelEncoderOptions options;
  options.frame_shape = frame_shape;
  options.num_layers = config.num_conv_layers;
  options.num_filters = config.num_filters;
  options.feature_dim = config.encoder_feature_dim;
  return options;
}

const std::vector<int64_t>& RequireFrames(const std::vector<int64_t>& frame_shape) {
  if (frame_shape.empty()) {
    throw ConfigError("SAC-AE learns from pixel frames: give it the frame shape (the envs need "
                      "obs=pixels)");
  }
  return frame_shape;
}

}  // namespace

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
  Require(std::isfinite(encoder_lr) && encoder_lr > 0, "encoder_lr", "finite and > 0",
          encoder_lr);
  Require(std::isfinite(decoder_lr) && decoder_lr > 0, "decoder_lr", "finite and > 0",
          decoder_lr);
  Require(std::isfinite(decoder_weight_decay) && decoder_weight_decay >= 0,
          "decoder_weight_decay", "finite and >= 0", decoder_weight_decay);
  Require(std::isfinite(decoder_latent_lambda) && decoder_latent_lambda >= 0,
          "decoder_latent_lambda", "finite and >= 0", decoder_latent_lambda);
  Require(decoder_update_freq >= 1 && decoder_update_freq <= 1000000, "decoder_update_freq",
          "in [1, 1000000]", decoder_update_freq);
}

SacAeLearner::SacAeLearner(const SacAeConfig& config, int64_t obs_dim, int64_t action_dim,
                           int64_t num_tasks, const std::vector<int64_t>& frame_shape)
    : config_(Validated(config)),
      sac_(config, obs_dim, action_dim, num_tasks, {}, RequireFrames(frame_shape)),
      encoder_optimizer_(sac_.pixel_encoder()->num_params(), Adam(config, config.encoder_lr)),
      decoder_optimizer_(0, Adam(config, config.decoder_lr, config.decoder_weight_decay)) {
  decoder_ = nn::PixelDecoder(EncoderOptions(config, frame_shape), config.encoder_feature_dim,
                              sac_.generator());
  decoder_optimizer_ = nn::FlatAdam(decoder_->num_params(),
                                    Adam(config, config.decoder_lr, config.decoder_weight_decay));
}

torch::Tensor SacAeLearner::AutoencoderLoss(const Batch& batch, at::Generator& generator) {
  nn::PixelEncoder& encoder = sac_.pixel_encoder();
  const torch::Tensor h = encoder->Forward(batch.pixels, encoder->params());
  const torch::Tensor reconstruction = decoder_->Forward(h, decoder_->params());
  const torch::Tensor target =
      nn::PreprocessFrames(batch.pixels, generator).reshape(reconstruction.sizes());
  const torch::Tensor latent = 0.5 * h.square().sum(1).mean();
  return torch::mse_loss(reconstruction, target) + config_.decoder_latent_lambda * latent;
}

Metrics SacAeLearner::Update(const Batch& batch) {
  // SAC validates the batch (frames included) before any step
  const int64_t update = sac_.num_updates();
  Metrics metrics = sac_.Update(batch);
  if (update % config_.decoder_update_freq != 0) return metrics;
  nn::PixelEncoder& encoder = sac_.pixel_encoder();
  encoder->ZeroGrad();
  decoder_->ZeroGrad();
  const torch::Tensor loss = AutoencoderLoss(batch, sac_.generator());
  loss.backward();
  encoder_optimizer_.Step(encoder->flat(), encoder->flat_grad());
  decoder_optimizer_.Step(decoder_->flat(), decoder_->flat_grad());
  const double total = loss.item<double>();
  metrics.Set("ae_loss", total);
  return metrics;
}

void SacAeLearner::Save(torch::serialize::OutputArchive& archive) const {
  sac_.Save(archive);
  Transfer(archive, "decoder", *decoder_);
  Transfer(archive, "ae_encoder_optimizer", encoder_optimizer_);
  Transfer(archive, "decoder_optimizer", decoder_optimizer_);
}

void SacAeLearner::Load(torch::serialize::InputArchive& archive) {
  sac_.Load(archive);
  Transfer(archive, "decoder", *decoder_);
  Transfer(archive, "ae_encoder_optimizer", encoder_optimizer_);
  Transfer(archive, "decoder_optimizer", decoder_optimizer_);
}

}  // namespace manyworlds::agents
