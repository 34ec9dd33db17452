// DeepMDP (Gelada et al. 2019) as MTRL's agent/deepmdp.py runs it on pixel
// frames: SAC-AE whose latent is also shaped by a latent transition model
// and a reward model, and whose decoder reconstructs the NEXT frame from the
// predicted next latent. HiP-BMDP (agents/hipbmdp) is this learner with a
// learned task parameter in the latent.
//
// The latent h(o, task): the pixel encoder's features (sac_config.h), with
// architecture task_encoder also the task's encoding theta (HiP-BMDP).
// One update, in MTRL's order:
//  1. SAC's update on the frames (agents/sac/sac.h);
//  2. transition and reward: (mu, sigma) = T([h(o), a]) against the detached
//     next latent h(o'): mean(0.5 ((mu - h(o')) / sigma)^2 + log sigma), plus
//     MSE(R(mu), r); one backward into T, R and the encoder (and theta);
//     Adam steps of T, R and the encoder;
//  3. every decoder_update_freq updates, the decoder on the next frame:
//     MSE(D(mu(h(o), a)), preprocess(o')) + decoder_latent_lambda * mean(0.5 |h(o)|^2)
//     into T, D and the encoder (and theta); Adam steps of T, D and the encoder;
//  4. (HiP-BMDP) the contrastive step and one Adam step of the task encoder
//     with everything theta gathered in 2-4.
// T and R use the decoder's optimiser settings (decoder_lr,
// decoder_weight_decay) and the encoder its own (encoder_lr), as MTRL's
// configs point them at the same optimiser files.
// With config.pcgrad or config.gradnorm steps 2 and 3 too go through them
// (MTRL's pcgrad_deepmdp and gradnorm_deepmdp route every loss through their
// _compute_gradient; GradNorm keeps one set of task weights per step, as
// MTRL keeps one per component list).
// Metrics: SAC's, transition_loss, reward_loss, and on decoder steps ae_loss;
// with pcgrad also pcgrad_model_conflicts and pcgrad_decoder_conflicts,
// with gradnorm gradnorm_model_loss and gradnorm_decoder_loss.
//
// Defaults are SAC-AE's (MTRL's DeepMind Control setup, sac_ae.h) plus MTRL's
// transition model (config/agent/components/hipbmdp_transition_model.yaml:
// deterministic, layer width 512) and reward decoder (width 512).
// Differences from MTRL: the actor reads the critic's encoder detached
// (sac_config.h); the reward is regressed on (B) values, MTRL's (B, 1).
#ifndef MANYWORLDS_AGENTS_DEEPMDP_DEEPMDP_H_
#define MANYWORLDS_AGENTS_DEEPMDP_DEEPMDP_H_

#include <cstdint>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/agents/deepmdp/latent_models.h"
#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/sac/sac.h"
#include "manyworlds/agents/sac_ae/sac_ae.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/gradnorm.h"
#include "manyworlds/nn/pixel_encoder.h"

namespace manyworlds::agents {

struct DeepMdpConfig : SacAeConfig {
  int64_t transition_width = 512;    // MTRL's layer_width
  bool probabilistic_transition = false;
  int64_t reward_width = 512;        // MTRL's RewardDecoder hidden width

  template <class F>
  void VisitFields(F&& f) {
    SacAeConfig::VisitFields(f);
    MANYWORLDS_VISIT_FIELDS(f, transition_width, probabilistic_transition, reward_width);
  }
  // Throws ConfigError naming the first bad field.
  void Validate() const;
};

class DeepMdpLearner : public OffPolicyLearner {
 public:
  // frame_shape (C, H, W) is required. contrastive_alpha > 0 (HiP-BMDP, with
  // architecture task_encoder and critic_trains_task_encoder off): the
  // contrastive loss on the task encodings, weighted so.
  DeepMdpLearner(const DeepMdpConfig& config, int64_t obs_dim, int64_t action_dim,
                 int64_t num_tasks, const std::vector<int64_t>& frame_shape,
                 double contrastive_alpha = 0.0);

  Metrics Update(const Batch& batch) override;
  Actor& AsActor() override { return sac_; }
  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive) override;

  SacLearner& sac() { return sac_; }
  TransitionModel& transition() { return transition_; }
  RewardDecoder& reward() { return reward_; }
  nn::PixelDecoder& decoder() { return decoder_; }
  // GradNorm's state of the model and decoder steps (weights undefined
  // without config.gradnorm).
  const nn::GradNormState& gradnorm_model() const { return gradnorm_model_; }
  const nn::GradNormState& gradnorm_decoder() const { return gradnorm_decoder_; }
  // The latent of frames (B, ...) of tasks (B), differentiable in the
  // encoder (and the task encoder) unless detached. Exposed for tests.
  torch::Tensor Latent(const torch::Tensor& frames, const torch::Tensor& task_index) const;
  // Mean squared error of R(mu(h(o), a)) against the batch's rewards, no
  // step. Exposed for tests.
  double RewardError(const Batch& batch) const;

 private:
  void ZeroTaskEncoderGrad();
  // Backpropagates the per-row losses (B) into `modules` (and the task
  // encoder this learner trains) by AuxiliaryBackward (sac_ae.h), with
  // `gradnorm` and its `last_layers` under config.gradnorm; under PCGrad
  // theta's earlier gradient is kept. Returns what AuxiliaryBackward does.
  double Backward(const torch::Tensor& per_sample, const torch::Tensor& task_index,
                  std::vector<nn::FlatModule*> modules, bool own_theta,
                  nn::GradNormState& gradnorm, const std::vector<torch::Tensor>& last_layers);
  // The models and optimisers beside SAC's, in Save's order (Self is const for Save).
  template <typename Archive, typename Self>
  static void TransferModels(Archive& archive, Self& self);

  DeepMdpConfig config_;
  double contrastive_alpha_;
  SacLearner sac_;
  bool task_latent_;  // the latent holds the task encoding (architecture task_encoder)
  TransitionModel transition_{nullptr};
  RewardDecoder reward_{nullptr};
  nn::PixelDecoder decoder_{nullptr};
  nn::FlatAdam encoder_optimizer_;
  nn::FlatAdam transition_optimizer_;
  nn::FlatAdam reward_optimizer_;
  nn::FlatAdam decoder_optimizer_;
  nn::FlatAdam task_encoder_optimizer_;  // HiP-BMDP: the task encoder's own
  // GradNorm of the model and decoder losses; off unless config.gradnorm
  nn::GradNormState gradnorm_model_, gradnorm_decoder_;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_DEEPMDP_DEEPMDP_H_
