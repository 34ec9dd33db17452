// TE-PPO: PPO with learned task embeddings (Hausman et al., "Learning an
// Embedding Space for Transferable Robot Skills", ICLR 2018), with the
// terms of garage's TEPPO (src/garage/tf/algos/te_npo.py).
//
// Networks:
//   encoder    q(z | task): Gaussian over a latent z in R^Z from the one-hot
//              task id (tanh MLP, tanh mean, learned std in [min, max]);
//   policy     pi(a | s, z): the Gaussian (or categorical) MLP policy of the
//              on-policy family on [s, z];
//   inference  q(z | s_t..s_{t+W-1}): Gaussian over z from a forward-looking
//              window of W observations (the episode's last observation
//              repeated past its end), trained by maximum likelihood;
//   baseline   linear features (or a value MLP) of [s, one-hot, z].
// Acting: a latent is drawn from the encoder when an episode begins and held
// for the whole episode (ActorState.latent); deterministic acting uses the
// encoder's mean.
// Update, per iteration:
//  1. rewards r_t - ce_coeff * CE_t + entropy_coeff * H_t, with
//     CE_t = clip(-log q(z | window_t), -3, 3) and H_t = -log pi(a_t | s_t, z)
//     (both through softplus with softplus_entropy), entropy_method "max";
//  2. GAE on those rewards with the baseline, advantages centred;
//  3. PPO epochs on the clipped surrogate of pi(a | s, z(theta)), where
//     z(theta) = mu_theta(task) + sigma_theta(task) * eps re-uses each step's
//     sampling noise eps, so the surrogate's gradient reaches the encoder,
//     minus encoder_entropy_coeff * mean over tasks of H(q(z | task));
//  4. inference epochs on -mean(gamma^t log q(z | window_t)).
// Metrics add inference_ce, reward_bonus, encoder_entropy, inference_loss,
// inference_rmse (of the inference means against the episode latents) and
// latent_min_distance (the closest two tasks' encoder means).
// Where this differs from garage's TF TEPPO, on purpose: garage evaluates
// the surrogate at the encoder's mean while acting on sampled latents (the
// ratio then compares two different conditionings); it scores CE_t with a
// fresh encoder sample instead of the episode's latent; and its encoder
// entropy term has a stopped gradient (a constant in the loss). Here the
// surrogate uses the latent that produced the actions, CE_t that same
// latent, and the encoder entropy is differentiable.
#ifndef MANYWORLDS_AGENTS_TE_PPO_TE_PPO_H_
#define MANYWORLDS_AGENTS_TE_PPO_TE_PPO_H_

#include <cstdint>
#include <memory>

#include <torch/torch.h>

#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/policy_gradient/policy_gradient.h"
#include "manyworlds/agents/te_ppo/te_ppo_config.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/stochastic_policy.h"
#include "manyworlds/rl/linear_baseline.h"

namespace manyworlds::agents {

class TePpoLearner : public OnPolicyLearner, public Actor {
 public:
  TePpoLearner(const TePpoConfig& config, const PolicySpaces& spaces);

  Actor& AsActor() override { return *this; }
  ActorState Initial(int64_t num_envs) override;
  ActOutput Act(const torch::Tensor& obs, const torch::Tensor& task_index, ActorState& state,
                ActMode mode) override;
  // Every scope starts a new episode: the envs' latents are drawn again.
  void Reset(const torch::Tensor& envs, ResetScope scope, ActorState& state) override;
  Metrics Update(rl::RolloutBuffer& rollout) override;

  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive) override;

  int64_t num_updates() const override { return num_updates_; }
  const TePpoConfig& config() const { return config_; }
  // The encoder's mean latent of every task, (num_tasks, Z).
  torch::Tensor TaskLatentMeans() const;
  // Inference-network inputs for every step of a rollout: obs (T, N, D) and
  // ended (T, N) 0/1 -> (T * N, window * D), row t * N + n holding
  // s_t, ..., s_{t+window-1} of env n, repeating the episode's last
  // observation past the step where it ended.
  static torch::Tensor InferenceWindows(const torch::Tensor& obs, const torch::Tensor& ended,
                                        int64_t window);

 private:
  // The checkpoint's networks and optimizers in Save's order; Load reads the
  // same list (Self is const for Save).
  template <typename Archive, typename Self>
  static void TransferNetworks(Archive& archive, Self& self);
  torch::Tensor OneHot(const torch::Tensor& task_index) const;
  torch::Tensor BaselineInput(const torch::Tensor& obs, const torch::Tensor& one_hot,
                              const torch::Tensor& latent) const;
  torch::Tensor Values(const torch::Tensor& x, const torch::Tensor& t) const;

  TePpoConfig config_;
  PolicySpaces spaces_;
  at::Generator generator_;
  nn::StochasticPolicy policy_{nullptr};
  nn::StochasticPolicy encoder_{nullptr};
  nn::StochasticPolicy inference_{nullptr};
  nn::ValueNetwork value_{nullptr};
  std::unique_ptr<rl::LinearFeatureBaseline> linear_;
  nn::FlatAdam policy_optimizer_;
  nn::FlatAdam encoder_optimizer_;
  nn::FlatAdam inference_optimizer_;
  nn::FlatAdam value_optimizer_;
  int64_t num_updates_ = 0;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_TE_PPO_TE_PPO_H_
