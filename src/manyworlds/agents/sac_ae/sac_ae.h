// SAC-AE (Yarats et al. 2019, "Improving Sample Efficiency in Model-Free
// Reinforcement Learning from Images"; MTRL's agent/sac_ae.py): SAC on pixel
// frames whose convolutional encoder is also trained by a deconvolutional
// decoder's reconstruction loss.
//
//   SacAeLearner learner(config, obs_dim, action_dim, num_tasks, {9, 84, 84});
//   Metrics m = learner.Update(batch);  // batch.pixels, batch.next_pixels filled
//
// One update:
//  1. SAC's update on the frames (agents/sac/sac.h with a pixel encoder:
//     critic loss into the critics and the encoder, actor on detached
//     features, temperature, targets, the encoder's target with encoder_tau);
//  2. every decoder_update_freq updates, the autoencoder step: h = encoder(o)
//     (the critic's encoder, online), reconstruction loss
//     MSE(decoder(h), preprocess(o)) + decoder_latent_lambda * mean(0.5 |h|^2),
//     preprocess being SAC-AE's 5-bit quantisation with uniform
//     dequantisation noise, mapped to [-0.5, 0.5]; one backward into encoder
//     and decoder, an Adam step of each (the encoder's own Adam state,
//     encoder_lr; the decoder's with L2 weight decay decoder_weight_decay).
// In MTRL's order: SAC's steps first, then the decoder. With config.pcgrad
// or config.gradnorm the autoencoder step too goes through them
// (AuxiliaryBackward below; MTRL's pcgrad_sac_ae and gradnorm agents route
// every loss through their _compute_gradient). Metrics: SAC's, and on
// decoder steps ae_loss (reconstruction plus latent penalty), with pcgrad
// also pcgrad_ae_conflicts, with gradnorm gradnorm_ae_loss.
//
// Defaults are MTRL's for its DeepMind Control (HiP-BMDP) setup:
// config/agent/sac_ae.yaml and config/agent/{components,optimizers}/hipbmdp_*.yaml:
// actor and critics 2 x 1024, log-std in [-10, 2], Adam 1e-3 for actor,
// critics, encoder and decoder (decoder weight decay 1e-7), temperature 0.1
// with Adam 1e-4, actor and targets every 2 updates, critic tau 0.01, encoder
// tau 0.05, encoder 4 x 32 convolutions to 50 features.
// Differences: decoder_latent_lambda defaults to the paper's 1e-6 (MTRL's
// config sets 0.0); MTRL's temperature Adam uses betas (0.5, 0.999), ours the
// betas every optimiser shares (adam_beta1, adam_beta2: 0.9, 0.999); the actor
// reads the critic's encoder detached (sac_config.h says why).
#ifndef MANYWORLDS_AGENTS_SAC_AE_SAC_AE_H_
#define MANYWORLDS_AGENTS_SAC_AE_SAC_AE_H_

#include <cstdint>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/sac/sac.h"
#include "manyworlds/agents/sac/sac_config.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/gradnorm.h"
#include "manyworlds/nn/pixel_encoder.h"

namespace manyworlds::agents {

struct SacAeConfig : SacConfig {
  double encoder_lr = 1e-3;             // the encoder's Adam in the autoencoder step
  double decoder_lr = 1e-3;
  double decoder_weight_decay = 1e-7;   // L2, as torch.optim.Adam's weight_decay
  double decoder_latent_lambda = 1e-6;  // the latent L2 penalty (MTRL's config: 0.0)
  int64_t decoder_update_freq = 1;      // autoencoder step every k updates

  SacAeConfig();
  template <class F>
  void VisitFields(F&& f) {
    SacConfig::VisitFields(f);
    MANYWORLDS_VISIT_FIELDS(f, encoder_lr, decoder_lr, decoder_weight_decay,
                            decoder_latent_lambda, decoder_update_freq);
  }
  // Throws ConfigError naming the first bad field.
  void Validate() const;
};

// How a pixel learner's own per-row loss (B) of tasks task_index (B) reaches
// `modules` (their gradients are zeroed by the caller): its mean; with
// pcgrad PCGrad's combination of the per-task gradients; with gradnorm the
// mean weighted per row by `gradnorm`'s task weights, which then take a
// GradNorm step with the norms of the per-task gradients in `last_layers`
// (MTRL's get_last_shared_layers: the decoder's last deconvolution, the
// transition model's mean layer, the reward model's output layer; the
// weights only, as SAC's GradNorm). Returns PCGrad's conflict fraction,
// GradNorm's loss, or 0.
double AuxiliaryBackward(SacLearner& sac, const torch::Tensor& per_sample,
                         const torch::Tensor& task_index,
                         const std::vector<nn::FlatModule*>& modules,
                         nn::GradNormState& gradnorm, const std::vector<torch::Tensor>& last_layers);

class SacAeLearner : public OffPolicyLearner {
 public:
  // frame_shape: (C, H, W) of the frames (required). Throws ConfigError on a
  // bad config or an empty frame shape.
  SacAeLearner(const SacAeConfig& config, int64_t obs_dim, int64_t action_dim, int64_t num_tasks,
               const std::vector<int64_t>& frame_shape);

  Metrics Update(const Batch& batch) override;
  Actor& AsActor() override { return sac_; }
  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive) override;

  SacLearner& sac() { return sac_; }
  nn::PixelDecoder& decoder() { return decoder_; }
  // GradNorm's state of the autoencoder step (weights undefined without
  // config.gradnorm).
  const nn::GradNormState& gradnorm() const { return gradnorm_; }
  // The autoencoder loss of each row of a batch, (B) (no step;
  // dequantisation noise from `generator`); the step minimises its mean.
  // Exposed for tests.
  torch::Tensor AutoencoderLoss(const Batch& batch, at::Generator& generator);

 private:
  SacAeConfig config_;
  SacLearner sac_;
  nn::PixelDecoder decoder_{nullptr};
  nn::FlatAdam encoder_optimizer_;
  nn::FlatAdam decoder_optimizer_;
  nn::GradNormState gradnorm_;  // the autoencoder loss's; off unless config.gradnorm
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_SAC_AE_SAC_AE_H_
