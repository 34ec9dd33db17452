#include "manyworlds/agents/deepmdp/deepmdp.h"

#include <string>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"

namespace manyworlds::agents {
namespace {

// GradNorm's last shared layers among the models' parameters (latent_models.cc's order): the
// transition model's mean layer weight and the reward model's output layer weight.
constexpr size_t kTransitionMeanWeight = 4;
constexpr size_t kRewardOutputWeight = 4;

}  // namespace

void DeepMdpConfig::Validate() const {
  SacAeConfig::Validate();
  RequireField(transition_width >= 1 && transition_width <= 65536, "transition_width",
               "in [1, 65536]", transition_width);
  RequireField(reward_width >= 1 && reward_width <= 65536, "reward_width", "in [1, 65536]",
               reward_width);
}

DeepMdpLearner::DeepMdpLearner(const DeepMdpConfig& config, int64_t obs_dim, int64_t action_dim,
                               int64_t num_tasks, const std::vector<int64_t>& frame_shape,
                               double contrastive_alpha)
    : config_(Validated(config)),
      contrastive_alpha_(contrastive_alpha),
      sac_(config, obs_dim, action_dim, num_tasks, {}, RequireFrameShape(frame_shape, "DeepMDP")),
      task_latent_(config.architecture == "task_encoder"),
      encoder_optimizer_(sac_.pixel_encoder()->num_params(), SacAdamOptions(config, config.encoder_lr)),
      transition_optimizer_(0, SacAdamOptions(config, config.decoder_lr)),
      reward_optimizer_(0, SacAdamOptions(config, config.decoder_lr)),
      decoder_optimizer_(0, SacAdamOptions(config, config.decoder_lr)),
      task_encoder_optimizer_(0, SacAdamOptions(config, config.encoder_lr)) {
  if (contrastive_alpha > 0.0 && (!task_latent_ || config.critic_trains_task_encoder)) {
    throw ConfigError("the contrastive task loss needs architecture task_encoder with "
                      "critic_trains_task_encoder false (HiP-BMDP's setting)");
  }
  const int64_t latent = config.encoder_feature_dim + (task_latent_ ? config.task_embedding_dim : 0);
  at::Generator& gen = sac_.generator();
  transition_ = TransitionModel(latent, action_dim, config.transition_width,
                                config.probabilistic_transition, gen);
  reward_ = RewardDecoder(latent, config.reward_width, gen);
  decoder_ = nn::PixelDecoder(SacPixelEncoderOptions(config, frame_shape), latent, gen);
  const nn::AdamOptions decay = SacAdamOptions(config, config.decoder_lr, config.decoder_weight_decay);
  transition_optimizer_ = nn::FlatAdam(transition_->num_params(), decay);
  reward_optimizer_ = nn::FlatAdam(reward_->num_params(), decay);
  decoder_optimizer_ = nn::FlatAdam(decoder_->num_params(), decay);
  if (task_latent_) {
    task_encoder_optimizer_ =
        nn::FlatAdam(sac_.task_encoder()->num_params(), SacAdamOptions(config, config.encoder_lr));
  }
  if (config.gradnorm) {
    gradnorm_model_ = nn::GradNormState(num_tasks, SacAdamOptions(config, config.gradnorm_lr));
    gradnorm_decoder_ = nn::GradNormState(num_tasks, SacAdamOptions(config, config.gradnorm_lr));
  }
}

torch::Tensor DeepMdpLearner::Latent(const torch::Tensor& frames,
                                     const torch::Tensor& task_index) const {
  const nn::PixelEncoder& encoder = sac_.pixel_encoder();
  const torch::Tensor h = encoder->Forward(frames, encoder->params());
  if (!task_latent_) return h;
  // theta is this learner's to train unless the critic trains it
  const nn::TaskEncoder& theta = sac_.task_encoder();
  const torch::Tensor z = config_.critic_trains_task_encoder
                              ? theta->Encode(theta->detached_params())
                              : theta->Encode(theta->params());
  return torch::cat({h, z.index_select(0, task_index)}, 1);
}

double DeepMdpLearner::RewardError(const Batch& batch) const {
  torch::NoGradGuard no_grad;
  const torch::Tensor h = Latent(batch.pixels, batch.task_index);
  const torch::Tensor mu =
      transition_->Forward(torch::cat({h, batch.action}, 1), transition_->params()).first;
  return torch::mse_loss(reward_->Forward(mu, reward_->params()), batch.reward).item<double>();
}

void DeepMdpLearner::ZeroTaskEncoderGrad() { sac_.task_encoder()->ZeroGrad(); }

double DeepMdpLearner::Backward(const torch::Tensor& per_sample, const torch::Tensor& task_index,
                                std::vector<nn::FlatModule*> modules, bool own_theta,
                                nn::GradNormState& gradnorm,
                                const std::vector<torch::Tensor>& last_layers) {
  // PCGrad leaves its combined gradient in the modules: theta's, gathered over the update's
  // losses, is kept aside and added back
  const bool theta_aside = own_theta && config_.pcgrad;
  torch::Tensor gathered;
  if (theta_aside) {
    gathered = sac_.task_encoder()->flat_grad().clone();
    modules.push_back(sac_.task_encoder().get());
  }
  const double combined =
      AuxiliaryBackward(sac_, per_sample, task_index, modules, gradnorm, last_layers);
  if (theta_aside) sac_.task_encoder()->flat_grad().add_(gathered);
  return combined;
}

Metrics DeepMdpLearner::Update(const Batch& batch) {
  const int64_t update = sac_.num_updates();
  Metrics metrics = sac_.Update(batch);  // validates the batch, frames included
  nn::PixelEncoder& encoder = sac_.pixel_encoder();
  const bool own_theta = task_latent_ && !config_.critic_trains_task_encoder;
  if (own_theta) ZeroTaskEncoderGrad();

  // transition and reward models
  encoder->ZeroGrad();
  transition_->ZeroGrad();
  reward_->ZeroGrad();
  {
    const torch::Tensor h = Latent(batch.pixels, batch.task_index);
    torch::Tensor next_h;
    {
      torch::NoGradGuard no_grad;
      next_h = Latent(batch.next_pixels, batch.task_index);
    }
    const auto [mu, sigma] =
        transition_->Forward(torch::cat({h, batch.action}, 1), transition_->params());
    // per row: the next latent's negative log-likelihood (up to a constant), the reward's error
    const torch::Tensor transition_loss =
        (sigma.defined() ? 0.5 * ((mu - next_h) / sigma).square() + sigma.log()
                         : 0.5 * (mu - next_h).square())
            .mean(1);
    const torch::Tensor reward_loss =
        (reward_->Forward(mu, reward_->params()) - batch.reward).square();
    const double combined =
        Backward(transition_loss + reward_loss, batch.task_index,
                 {transition_.get(), reward_.get(), encoder.get()}, own_theta, gradnorm_model_,
                 {transition_->params()[kTransitionMeanWeight],
                  reward_->params()[kRewardOutputWeight]});
    transition_optimizer_.Step(transition_->flat(), transition_->flat_grad());
    reward_optimizer_.Step(reward_->flat(), reward_->flat_grad());
    encoder_optimizer_.Step(encoder->flat(), encoder->flat_grad());
    metrics.Set("transition_loss", transition_loss.mean().item<double>());
    metrics.Set("reward_loss", reward_loss.mean().item<double>());
    if (config_.pcgrad) metrics.Set("pcgrad_model_conflicts", combined);
    if (config_.gradnorm) metrics.Set("gradnorm_model_loss", combined);
  }

  // the decoder, on the next frame from the predicted next latent
  if (update % config_.decoder_update_freq == 0) {
    encoder->ZeroGrad();
    transition_->ZeroGrad();
    decoder_->ZeroGrad();
    const torch::Tensor h = Latent(batch.pixels, batch.task_index);
    const torch::Tensor mu =
        transition_->Forward(torch::cat({h, batch.action}, 1), transition_->params()).first;
    const torch::Tensor reconstruction = decoder_->Forward(mu, decoder_->params());
    const torch::Tensor target = nn::PreprocessFrames(batch.next_pixels, sac_.generator())
                                     .reshape(reconstruction.sizes());
    const torch::Tensor per_sample = (reconstruction - target).square().flatten(1).mean(1) +
                                     config_.decoder_latent_lambda * 0.5 * h.square().sum(1);
    const auto& decoder_params = decoder_->params();
    const double combined =
        Backward(per_sample, batch.task_index, {transition_.get(), decoder_.get(), encoder.get()},
                 own_theta, gradnorm_decoder_,
                 {transition_->params()[kTransitionMeanWeight],
                  decoder_params[decoder_params.size() - 2]});
    transition_optimizer_.Step(transition_->flat(), transition_->flat_grad());
    decoder_optimizer_.Step(decoder_->flat(), decoder_->flat_grad());
    encoder_optimizer_.Step(encoder->flat(), encoder->flat_grad());
    metrics.Set("ae_loss", per_sample.mean().item<double>());
    if (config_.pcgrad) metrics.Set("pcgrad_decoder_conflicts", combined);
    if (config_.gradnorm) metrics.Set("gradnorm_decoder_loss", combined);
  }

  if (own_theta) {
    nn::TaskEncoder& theta_encoder = sac_.task_encoder();
    if (contrastive_alpha_ > 0.0) {
      // MTRL's update_task_encoder: the distance between each row's task parameter and the
      // batch-reversed one should equal the distance between the transitions they predict
      // (both norms over the whole batch; the predictions detached, so only theta learns)
      const torch::Tensor theta =
          theta_encoder->Encode(theta_encoder->params()).index_select(0, batch.task_index);
      const torch::Tensor flipped = theta.flip({0});
      torch::Tensor prediction_gap;
      {
        torch::NoGradGuard no_grad;
        const torch::Tensor phi = encoder->Forward(batch.pixels, encoder->detached_params());
        auto predict = [&](const torch::Tensor& t) {
          return transition_
              ->Forward(torch::cat({phi, t, batch.action}, 1), transition_->detached_params())
              .first;
        };
        prediction_gap = (predict(theta.detach()) - predict(flipped.detach())).norm();
      }
      const torch::Tensor loss = (theta - flipped).norm() - prediction_gap;
      const torch::Tensor weighted = contrastive_alpha_ * loss.square();
      weighted.backward();
      metrics.Set("contrastive_loss", loss.square().item<double>());
    }
    task_encoder_optimizer_.Step(theta_encoder->flat(), theta_encoder->flat_grad());
  }
  return metrics;
}

template <typename Archive, typename Self>
void DeepMdpLearner::TransferModels(Archive& archive, Self& self) {
  Transfer(archive, "transition", *self.transition_);
  Transfer(archive, "reward_decoder", *self.reward_);
  Transfer(archive, "decoder", *self.decoder_);
  Transfer(archive, "model_encoder_optimizer", self.encoder_optimizer_);
  Transfer(archive, "transition_optimizer", self.transition_optimizer_);
  Transfer(archive, "reward_optimizer", self.reward_optimizer_);
  Transfer(archive, "decoder_optimizer", self.decoder_optimizer_);
  if (self.task_latent_) Transfer(archive, "theta_optimizer", self.task_encoder_optimizer_);
  if (self.config_.gradnorm) {
    Transfer(archive, "gradnorm_model", self.gradnorm_model_);
    Transfer(archive, "gradnorm_decoder", self.gradnorm_decoder_);
  }
}

void DeepMdpLearner::Save(torch::serialize::OutputArchive& archive) const {
  sac_.Save(archive);
  TransferModels(archive, *this);
}

void DeepMdpLearner::Load(torch::serialize::InputArchive& archive) {
  sac_.Load(archive);
  TransferModels(archive, *this);
}

}  // namespace manyworlds::agents
