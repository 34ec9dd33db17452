#include "manyworlds/agents/rl2/rl2.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/agents/ppo/ppo.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/threads.h"
#include "manyworlds/rl/generator.h"

namespace manyworlds::agents {
namespace {

// Names of this actor's ActorState entries.
constexpr char kHidden[] = "hidden";
constexpr char kRl2Context[] = "context";

// Marks an RL2 checkpoint (PPO/TRPO write their own algorithm code).
constexpr int64_t kRl2CheckpointCode = 0x726c32;  // "rl2"

}  // namespace

void Rl2Config::Validate() const {
  RequireField(hidden_dim > 0 && hidden_dim <= 65536, "hidden_dim", "in [1, 65536]", hidden_dim);
  RequireStdBounds("", min_std, max_std, init_std);
  RequireField(FinitePositive(lr), "lr", "finite and > 0", lr);
  RequireField(epochs >= 1 && epochs <= 10000, "epochs", "in [1, 10000]", epochs);
  RequireField(minibatch_trials >= 1 && minibatch_trials <= 1000000, "minibatch_trials",
               "in [1, 1e6]", minibatch_trials);
  RequireField(clip_range > 0 && clip_range < 1, "clip_range", "in (0, 1)", clip_range);
  RequireField(std::isfinite(max_grad_norm) && max_grad_norm >= 0, "max_grad_norm",
               "finite and >= 0", max_grad_norm);
  RequireDiscountAndLambda(discount, gae_lambda);
  RequireEntropyTerm(entropy_method, entropy_coeff);
  RequireField(episodes_per_trial >= 1 && episodes_per_trial <= 100000, "episodes_per_trial",
               "in [1, 100000]", episodes_per_trial);
  RequireField(std::isfinite(context_reward_scale), "context_reward_scale", "finite",
               context_reward_scale);
}

Rl2Learner::Rl2Learner(const Rl2Config& config, const PolicySpaces& spaces)
    : config_(Validated(config)),
      spaces_(spaces),
      // [a (one-hot for Discrete), r, d]
      context_dim_((spaces.num_actions > 0 ? spaces.num_actions : spaces.action_dim) + 2),
      generator_(rl::MakeGenerator(config.seed)),
      baseline_(spaces.obs_dim + context_dim_) {
  if (spaces.obs_dim <= 0 || spaces.action_dim <= 0) {
    throw ConfigError("rl2: obs_dim and action_dim must be > 0");
  }
  nn::ConfigureTorchThreads();
  const int64_t input_dim = spaces.obs_dim + context_dim_;
  gru_ = nn::Gru(input_dim, config.hidden_dim, generator_);
  nn::StochasticPolicyOptions head;
  head.input_dim = config.hidden_dim;
  head.action_dim = spaces.action_dim;
  head.num_actions = spaces.num_actions;
  head.num_layers = 0;  // linear from the GRU state
  head.init_std = config.init_std;
  head.min_std = config.min_std;
  head.max_std = config.max_std;
  head_ = nn::StochasticPolicy(head, generator_);
  modules_ = {gru_.get(), head_.get()};
  for (const nn::FlatModule* m : modules_) {
    optimizers_.emplace_back(m->num_params(), nn::AdamOptions{.lr = config.lr});
  }
}

torch::Tensor Rl2Learner::Context(const torch::Tensor& actions, const torch::Tensor& rewards,
                                  const torch::Tensor& ended) const {
  const torch::Tensor a =
      spaces_.num_actions > 0
          ? torch::one_hot(actions.squeeze(-1).to(torch::kInt64), spaces_.num_actions)
                .to(torch::kFloat32)
          : actions.clamp(-1.0, 1.0);
  return torch::cat(
      {a, (rewards * config_.context_reward_scale).unsqueeze(-1), ended.unsqueeze(-1)}, -1);
}

ActorState Rl2Learner::Initial(int64_t num_envs) {
  ActorState state;
  state.tensors[kHidden] = torch::zeros({num_envs, config_.hidden_dim});
  state.tensors[kRl2Context] = torch::zeros({num_envs, context_dim_});
  return state;
}

ActOutput Rl2Learner::Act(const torch::Tensor& obs, const torch::Tensor&, ActorState& state,
                          ActMode mode) {
  c10::InferenceMode inference;
  const int64_t n = obs.size(0);
  if (obs.dim() != 2 || obs.size(1) != spaces_.obs_dim) {
    throw Error("rl2 actor: expected obs (N, " + std::to_string(spaces_.obs_dim) + ")");
  }
  RestartUnlessSized(*this, state, kHidden, n);
  const torch::Tensor x = torch::cat({obs, state.tensors[kRl2Context]}, -1).unsqueeze(0);
  auto [out, h] = gru_->Forward(x, state.tensors[kHidden]);
  state.tensors[kHidden] = h;
  const nn::ActionDistribution d = head_->Forward(out[0]);
  ActOutput result;
  result.action =
      mode == ActMode::kSample ? d.Sample(SamplingGenerator(state, generator_)) : d.Mode();
  result.log_prob = d.LogProb(result.action);
  return result;
}

void Rl2Learner::Reset(const torch::Tensor& envs, ResetScope scope, ActorState& state) {
  if (scope == ResetScope::kEpisode) return;  // the trial goes on
  c10::InferenceMode inference;
  if (RestartUnlessSized(*this, state, kHidden, envs.size(0))) return;
  const torch::Tensor keep = envs.to(torch::kBool).logical_not().unsqueeze(1).to(torch::kFloat32);
  state.tensors[kHidden] = state.tensors[kHidden] * keep;
  state.tensors[kRl2Context] = state.tensors[kRl2Context] * keep;
}

void Rl2Learner::Observe(const StepOutcome& outcome, ActorState& state) {
  c10::InferenceMode inference;
  state.tensors[kRl2Context] = Context(outcome.action, outcome.reward, outcome.ended);
}

nn::ActionDistribution Rl2Learner::Unroll(const torch::Tensor& x) const {
  const torch::Tensor h0 = torch::zeros({x.size(1), config_.hidden_dim});
  const torch::Tensor out = gru_->Forward(x, h0).first;
  return head_->Forward(out.reshape({-1, config_.hidden_dim}));
}

Metrics Rl2Learner::Update(rl::RolloutBuffer& rollout) {
  const int64_t steps = rollout.steps();
  const int64_t envs = rollout.envs();
  // the policy's inputs: obs and the previous step's context (zeros first)
  torch::Tensor context = torch::zeros({steps, envs, context_dim_});
  if (steps > 1) {
    context.narrow(0, 1, steps - 1)
        .copy_(Context(rollout.actions.narrow(0, 0, steps - 1),
                       rollout.rewards.narrow(0, 0, steps - 1),
                       rollout.ended.narrow(0, 0, steps - 1)));
  }
  const torch::Tensor x = torch::cat({rollout.obs, context}, -1);  // (T, N, in)
  const torch::Tensor flat_x = x.reshape({steps * envs, -1});
  const torch::Tensor trial_step =
      torch::arange(steps, torch::kFloat32).unsqueeze(1).expand({steps, envs}).reshape({-1});

  // one sequence per trial, ending (terminally) at the trial's last step
  torch::Tensor trial_end = torch::zeros({steps, envs});
  trial_end[steps - 1].fill_(1.0f);
  const torch::Tensor no_bootstrap = torch::zeros({steps, envs});
  torch::Tensor rewards = rollout.rewards;
  if (config_.entropy_method == "max" && config_.entropy_coeff > 0) {
    rewards = rewards - config_.entropy_coeff * rollout.log_probs;
  }
  const torch::Tensor values = baseline_.Predict(flat_x, trial_step).reshape({steps, envs});
  RequireFinite(values, "rl2", "the baseline's values");
  const torch::Tensor advantages = rl::ComputeGae(
      rewards, values, trial_end, trial_end, no_bootstrap, config_.discount, config_.gae_lambda);
  const torch::Tensor mc_returns = rl::ComputeGae(rewards, torch::zeros_like(values), trial_end,
                                                  trial_end, no_bootstrap, config_.discount, 1.0);
  Metrics metrics;
  metrics.Set("explained_variance",
              ExplainedVariance(values.reshape({-1}), mc_returns.reshape({-1})));
  baseline_.Fit(flat_x, trial_step, mc_returns.reshape({-1}));
  torch::Tensor adv = advantages;
  if (config_.center_advantages && adv.numel() > 1) {
    adv = (adv - adv.mean()) / (adv.std() + 1e-8);
  }
  metrics.Set("trial_return", rollout.rewards.sum(0).mean().item<double>());

  const double regularizer = config_.entropy_method == "regularized" ? config_.entropy_coeff : 0.0;
  const int64_t mb = std::min(config_.minibatch_trials, envs);
  ClippedEpochSums sums;
  for (int64_t epoch = 0; epoch < config_.epochs; ++epoch) {
    const torch::Tensor perm = torch::randperm(envs, generator_, torch::kInt64);
    sums = {};
    for (int64_t lo = 0; lo < envs; lo += mb) {
      const torch::Tensor cols = perm.narrow(0, lo, std::min(mb, envs - lo));
      const nn::ActionDistribution d = Unroll(x.index_select(1, cols));
      const int64_t rows = steps * cols.size(0);
      const ClippedSurrogate surrogate =
          ClippedSurrogateLoss(d.LogProb(rollout.actions.index_select(1, cols).reshape({rows, -1})),
                               rollout.log_probs.index_select(1, cols).reshape({rows}),
                               adv.index_select(1, cols).reshape({rows}), config_.clip_range);
      const torch::Tensor ent = d.Entropy().mean();
      const torch::Tensor loss = surrogate.loss - regularizer * ent;
      for (nn::FlatModule* m : modules_) m->ZeroGrad();
      loss.backward();
      ClipGradNorm(modules_, config_.max_grad_norm);
      for (size_t i = 0; i < modules_.size(); ++i) {
        optimizers_[i].Step(modules_[i]->flat(), modules_[i]->flat_grad());
      }
      sums.Add(loss, ent, surrogate);
    }
  }
  for (const nn::FlatModule* m : modules_)
    RequireFinite(m->flat(), "rl2", "the policy's parameters");
  // the last epoch's means
  const auto count = static_cast<double>(sums.count);
  metrics.Set("policy_loss", sums.policy_loss / count);
  metrics.Set("entropy", sums.entropy / count);
  metrics.Set("approx_kl", sums.approx_kl / count);
  metrics.Set("clip_fraction", sums.clip_fraction / count);
  ++num_updates_;
  return metrics;
}

template <typename Archive, typename Self>
void Rl2Learner::TransferNetworks(Archive& archive, Self& self) {
  Transfer(archive, "gru", *self.gru_);
  Transfer(archive, "head", *self.head_);
  Transfer(archive, "gru_optimizer", self.optimizers_[0]);
  Transfer(archive, "head_optimizer", self.optimizers_[1]);
  Transfer(archive, "linear_baseline", self.baseline_);
}

void Rl2Learner::Save(torch::serialize::OutputArchive& archive) const {
  WriteSignature(archive, kRl2CheckpointCode, {spaces_.obs_dim, context_dim_, config_.hidden_dim});
  TransferNetworks(archive, *this);
  WriteProgress(archive, num_updates_, generator_);
}

void Rl2Learner::Load(torch::serialize::InputArchive& archive) {
  if (!HasSignature(archive, kRl2CheckpointCode,
                    {spaces_.obs_dim, context_dim_, config_.hidden_dim})) {
    throw Error("rl2 checkpoint: not a checkpoint of RL2 with these sizes");
  }
  TransferNetworks(archive, *this);
  ReadProgress(archive, num_updates_, generator_);
}

}  // namespace manyworlds::agents
