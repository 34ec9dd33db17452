// Distral (Teh et al., NeurIPS 2017, "Distral: Robust Multitask
// Reinforcement Learning"): one SAC agent per task, each regularised towards
// a distilled central policy pi_0 that is trained to be their centroid.
//
//   DistralLearner distral(config, obs_dim, action_dim, num_tasks);
//   Metrics m = distral.Update(batch);   // every task agent, then pi_0
//
// Task agent i maximises the return of the regularised reward
//   r + c_KL log pi_0(a|s) - (c_KL + c_Ent) log pi_i(a|s)
// (the paper's KL and entropy weights: c_KL = distral_alpha, c_Ent = the
// agent's learned SAC temperature), through SacLearner's prior
// (sac.h: the soft value and the actor loss get the c_KL terms). The
// distilled policy sees the observation only (no task id) and is trained by
// distillation: distral_alpha * KL(pi_i || pi_0) of the pre-tanh Gaussians
// on the batch's states, pi_i fixed, one Adam step per update.
//
// MTRL's implementation (mtrl/agent/distral.py, read as reference) has the
// same critic target. Differences: MTRL's actor loss omits the -c_KL log
// pi_0 term (its task policies see pi_0 only through the target), and it
// trains pi_0 on KL(pi_0 || pi_i), the reverse direction; we follow the
// paper in both (its centroid is the maximum-likelihood policy of the task
// policies' actions). MTRL evaluates with pi_0's mean; `act_with` chooses
// (default: the task policies, which are what solve the tasks when the
// observation does not say which task it is).
//
// pi_0 starts as N(0, 1) in pre-tanh space (distral.cc says why).
//
// Batches: rows of any task, in any order; each task agent updates on its
// own rows (a task absent from a batch skips that update). Task agent i's
// generator is seeded from seed and i, pi_0's from seed.
#ifndef MANYWORLDS_AGENTS_DISTRAL_DISTRAL_H_
#define MANYWORLDS_AGENTS_DISTRAL_DISTRAL_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/agents/actor.h"
#include "manyworlds/agents/batch.h"
#include "manyworlds/agents/learner.h"
#include "manyworlds/agents/metrics.h"
#include "manyworlds/agents/sac/sac.h"
#include "manyworlds/core/visit_fields.h"
#include "manyworlds/nn/flat_optim.h"
#include "manyworlds/nn/gaussian_policy.h"

namespace manyworlds::agents {

// Defaults: the task agents are MT-SAC's state settings (sac_config.h); the
// KL weight is MTRL's documented Distral command's (distral_alpha=1.0,
// docs_src/source/pages/tutorials/baseline.rst).
struct DistralConfig {
  double distral_alpha = 1.0;  // c_KL: the KL weight
  double distilled_lr = 3e-4;  // pi_0's Adam
  std::string act_with = "task";  // task | distilled: the policy Act uses
  // The task agents (SacConfig's meanings).
  int64_t hidden_dim = 400;
  int64_t num_layers = 3;
  double actor_lr = 3e-4;
  double critic_lr = 3e-4;
  double alpha_lr = 3e-4;
  double discount = 0.99;
  double tau = 0.005;
  double init_temperature = 1.0;
  int64_t batch_size = 128;  // per task
  std::optional<double> target_entropy;
  double log_std_min = -20.0;
  double log_std_max = 2.0;
  int64_t actor_update_freq = 1;
  int64_t critic_target_update_freq = 1;
  double max_critic_loss = 1e8;
  uint64_t seed = 0;

  template <class F>
  void VisitFields(F&& f) {
    MANYWORLDS_VISIT_FIELDS(f, distral_alpha, distilled_lr, act_with, hidden_dim, num_layers,
                            actor_lr, critic_lr, alpha_lr, discount, tau, init_temperature,
                            batch_size, target_entropy, log_std_min, log_std_max,
                            actor_update_freq, critic_target_update_freq, max_critic_loss, seed);
  }
  // Throws ConfigError naming the first bad field and its allowed range.
  void Validate() const;
  // Task agent `task`'s SAC config (single task, its own seed).
  SacConfig TaskAgentConfig(int64_t task) const;
};

class DistralLearner : public OffPolicyLearner, public Actor {
 public:
  DistralLearner(const DistralConfig& config, int64_t obs_dim, int64_t action_dim,
                 int64_t num_tasks);
  DistralLearner(const DistralLearner&) = delete;
  DistralLearner& operator=(const DistralLearner&) = delete;

  // Every task agent on its rows, then one distillation step of pi_0.
  // Metrics: the task agents' SAC metrics averaged over the tasks present,
  // distill_kl (mean KL(pi_i || pi_0) per row before the step).
  Metrics Update(const Batch& batch) override;

  ActOutput Act(const torch::Tensor& obs, const torch::Tensor& task_index, ActorState& state,
                ActMode mode) override;
  Actor& AsActor() override { return *this; }
  // Actions in (-1, 1): each row's task policy, or pi_0 (config.act_with).
  torch::Tensor Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                    bool deterministic);

  // log pi_0(tanh(u) | obs), (B); differentiable in u, not in pi_0's weights.
  torch::Tensor DistilledLogProb(const torch::Tensor& obs, const torch::Tensor& u) const;

  SacLearner& task_agent(int64_t task) { return *task_agents_[static_cast<size_t>(task)]; }
  nn::GaussianPolicy& distilled() { return distilled_; }
  int64_t num_updates() const { return num_updates_; }
  const DistralConfig& config() const { return config_; }

  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive) override;

 private:
  DistralConfig config_;
  int64_t obs_dim_, action_dim_, num_tasks_;
  std::vector<std::unique_ptr<SacLearner>> task_agents_;
  at::Generator generator_;  // pi_0's initialisation and sampling
  nn::GaussianPolicy distilled_{nullptr};
  nn::FlatAdam distilled_optimizer_;
  int64_t num_updates_ = 0;
};

}  // namespace manyworlds::agents

#endif  // MANYWORLDS_AGENTS_DISTRAL_DISTRAL_H_
