#include "manyworlds/agents/te_ppo/te_ppo.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
constexpr char kTePpoLatent[] = "latent";

torch::Tensor SoftplusIf(bool on, const torch::Tensor& x) { return on ? torch::softplus(x) : x; }

// The std bounds of a latent network: init, min, max.
struct StdBounds {
  double init, min, max;
};

// The task encoder's or the inference network's options: a Gaussian latent of
// latent_dim with a tanh-bounded mean and an output layer of gain 1, so that
// tasks start with distinct latents.
nn::StochasticPolicyOptions LatentNetworkOptions(int64_t input_dim, int64_t latent_dim,
                                                 int64_t hidden_dim, int64_t num_layers,
                                                 StdBounds std) {
  return {.input_dim = input_dim,
          .action_dim = latent_dim,
          .hidden_dim = hidden_dim,
          .num_layers = num_layers,
          .init_std = std.init,
          .min_std = std.min,
          .max_std = std.max,
          .output_gain = 1.0,
          .tanh_mean = true};
}

constexpr double kLogSqrt2PiE = 1.4189385332046727;  // 0.5 * log(2 pi e)

}  // namespace

void TePpoConfig::Validate() const {
  PpoConfig::Validate();
  RequireField(architecture == "mlp", "architecture",
               "mlp for te_ppo (the learned latent replaces the one-hot)", architecture);
  RequireField(latent_dim >= 1 && latent_dim <= 1024, "latent_dim", "in [1, 1024]", latent_dim);
  RequireField(encoder_hidden_dim >= 1 && encoder_hidden_dim <= 65536, "encoder_hidden_dim",
               "in [1, 65536]", encoder_hidden_dim);
  RequireField(encoder_num_layers >= 0 && encoder_num_layers <= 64, "encoder_num_layers",
               "in [0, 64]", encoder_num_layers);
  RequireStdBounds("encoder_", encoder_min_std, encoder_max_std, encoder_init_std);
  RequireField(std::isfinite(encoder_entropy_coeff) && encoder_entropy_coeff >= 0,
               "encoder_entropy_coeff", "finite and >= 0", encoder_entropy_coeff);
  RequireField(inference_window >= 1 && inference_window <= 1000, "inference_window",
               "in [1, 1000]", inference_window);
  RequireField(inference_hidden_dim >= 1 && inference_hidden_dim <= 65536, "inference_hidden_dim",
               "in [1, 65536]", inference_hidden_dim);
  RequireField(inference_num_layers >= 0 && inference_num_layers <= 64, "inference_num_layers",
               "in [0, 64]", inference_num_layers);
  RequireStdBounds("inference_", inference_min_std, inference_max_std, inference_init_std);
  RequireField(FinitePositive(inference_lr), "inference_lr", "finite and > 0", inference_lr);
  RequireField(inference_epochs >= 0 && inference_epochs <= 10000, "inference_epochs",
               "in [0, 10000]", inference_epochs);
  RequireField(inference_minibatch_size >= 1 && inference_minibatch_size <= 100000000,
               "inference_minibatch_size", "in [1, 1e8]", inference_minibatch_size);
  RequireField(std::isfinite(inference_ce_coeff) && inference_ce_coeff >= 0, "inference_ce_coeff",
               "finite and >= 0", inference_ce_coeff);
}

TePpoLearner::TePpoLearner(const TePpoConfig& config, const PolicySpaces& spaces)
    : config_(Validated(config)),
      spaces_(spaces),
      generator_(rl::MakeGenerator(config.seed)),
      policy_optimizer_(0, nn::AdamOptions{.lr = config.lr}),
      encoder_optimizer_(0, nn::AdamOptions{.lr = config.lr}),
      inference_optimizer_(0, nn::AdamOptions{.lr = config.inference_lr}),
      value_optimizer_(0, nn::AdamOptions{.lr = config.vf_lr}) {
  if (spaces.obs_dim <= 0 || spaces.action_dim <= 0 || spaces.num_tasks <= 0) {
    throw ConfigError("te_ppo learner: obs_dim, action_dim and num_tasks must be > 0");
  }
  nn::ConfigureTorchThreads();
  const int64_t z = config.latent_dim;
  policy_ = nn::StochasticPolicy(PolicyNetworkOptions(config, spaces, spaces.obs_dim + z),
                                 generator_);
  encoder_ = nn::StochasticPolicy(
      LatentNetworkOptions(
          spaces.num_tasks, z, config.encoder_hidden_dim, config.encoder_num_layers,
          {config.encoder_init_std, config.encoder_min_std, config.encoder_max_std}),
      generator_);
  inference_ = nn::StochasticPolicy(
      LatentNetworkOptions(config.inference_window * spaces.obs_dim, z,
                           config.inference_hidden_dim, config.inference_num_layers,
                           {config.inference_init_std, config.inference_min_std,
                            config.inference_max_std}),
      generator_);

  policy_optimizer_ = nn::FlatAdam(policy_->num_params(), nn::AdamOptions{.lr = config.lr});
  encoder_optimizer_ = nn::FlatAdam(encoder_->num_params(), nn::AdamOptions{.lr = config.lr});
  inference_optimizer_ =
      nn::FlatAdam(inference_->num_params(), nn::AdamOptions{.lr = config.inference_lr});
  const int64_t baseline_dim = spaces.obs_dim + spaces.num_tasks + z;
  if (config.baseline == "mlp") {
    value_ =
        nn::ValueNetwork(baseline_dim, config.vf_hidden_dim, config.vf_num_layers, 1, generator_);
    value_optimizer_ = nn::FlatAdam(value_->num_params(), nn::AdamOptions{.lr = config.vf_lr});
  } else {
    linear_ = std::make_unique<rl::LinearFeatureBaseline>(baseline_dim);
  }
}

torch::Tensor TePpoLearner::OneHot(const torch::Tensor& task_index) const {
  return torch::one_hot(task_index, spaces_.num_tasks).to(torch::kFloat32);
}

torch::Tensor TePpoLearner::BaselineInput(const torch::Tensor& obs, const torch::Tensor& one_hot,
                                          const torch::Tensor& latent) const {
  return torch::cat({obs, one_hot, latent}, -1);
}

torch::Tensor TePpoLearner::Values(const torch::Tensor& x, const torch::Tensor& t) const {
  torch::NoGradGuard no_grad;
  if (value_) return value_->Forward(x);
  return linear_->Predict(x, t);
}

torch::Tensor TePpoLearner::TaskLatentMeans() const {
  torch::NoGradGuard no_grad;
  return encoder_->Forward(torch::eye(spaces_.num_tasks, torch::kFloat32)).mean;
}

ActorState TePpoLearner::Initial(int64_t num_envs) {
  c10::InferenceMode inference;
  ActorState state;
  state.tensors[kTePpoLatent] = torch::full(
      {num_envs, config_.latent_dim}, std::numeric_limits<float>::quiet_NaN(), torch::kFloat32);
  return state;
}

void TePpoLearner::Reset(const torch::Tensor& envs, ResetScope, ActorState& state) {
  c10::InferenceMode inference;
  if (RestartUnlessSized(*this, state, kTePpoLatent, envs.size(0))) return;
  state.tensors[kTePpoLatent] = torch::where(
      envs.to(torch::kBool).unsqueeze(1), torch::full({}, std::numeric_limits<float>::quiet_NaN()),
      state.tensors[kTePpoLatent]);
}

ActOutput TePpoLearner::Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                            ActorState& state, ActMode mode) {
  c10::InferenceMode inference;
  const int64_t n = obs.size(0);
  if (obs.dim() != 2 || obs.size(1) != spaces_.obs_dim || task_index.dim() != 1 ||
      task_index.size(0) != n) {
    throw Error("te_ppo actor: expected obs (N, " + std::to_string(spaces_.obs_dim) +
                ") and task_index (N)");
  }
  torch::Tensor latent;
  if (mode == ActMode::kDeterministic) {
    latent = encoder_->Forward(OneHot(task_index)).mean;
  } else {
    RestartUnlessSized(*this, state, kTePpoLatent, n);
    const torch::Tensor fresh = state.tensors[kTePpoLatent].select(1, 0).isnan();
    if (fresh.any().item<bool>()) {  // the encoder runs only where episodes begin
      const torch::Tensor drawn =
          encoder_->Forward(OneHot(task_index)).Sample(SamplingGenerator(state, generator_));
      state.tensors[kTePpoLatent] =
          torch::where(fresh.unsqueeze(1), drawn, state.tensors[kTePpoLatent]);
    }
    latent = state.tensors[kTePpoLatent];
  }
  const nn::ActionDistribution d = policy_->Forward(torch::cat({obs, latent}, -1));
  ActOutput out;
  out.action = mode == ActMode::kSample ? d.Sample(SamplingGenerator(state, generator_)) : d.Mode();
  out.log_prob = d.LogProb(out.action);
  out.latent = latent;  // state updates replace state.tensors[kTePpoLatent], never write into it
  return out;
}

torch::Tensor TePpoLearner::InferenceWindows(const torch::Tensor& obs, const torch::Tensor& ended,
                                             int64_t window) {
  const int64_t steps = obs.size(0), envs = obs.size(1), d = obs.size(2);
  torch::Tensor win = torch::empty({steps, envs, window, d}, obs.options());
  for (int64_t t = steps - 1; t >= 0; --t) {
    const torch::Tensor here = obs[t].unsqueeze(1).expand({envs, window, d});
    if (t == steps - 1 || window == 1) {
      win[t].copy_(here);
      continue;
    }
    // ended at t: the window stays on s_t; else it continues with t + 1's window
    const torch::Tensor next =
        torch::cat({obs[t].unsqueeze(1), win[t + 1].narrow(1, 0, window - 1)}, 1);
    win[t].copy_(torch::where(ended[t].to(torch::kBool).view({envs, 1, 1}), here, next));
  }
  return win.reshape({steps * envs, window * d});
}

Metrics TePpoLearner::Update(rl::RolloutBuffer& rollout) {
  if (!rollout.latents.defined() || rollout.latents.size(2) != config_.latent_dim) {
    throw Error("te_ppo update: the rollout carries no latents of size " +
                std::to_string(config_.latent_dim));
  }
  const int64_t b = rollout.size();
  const int64_t num_tasks = spaces_.num_tasks;
  const torch::Tensor obs = rollout.FlatObs();
  const torch::Tensor tasks = rollout.FlatTasks();
  const torch::Tensor one_hot = OneHot(tasks);
  const torch::Tensor latent = rollout.latents.reshape({b, config_.latent_dim});
  const torch::Tensor t = rollout.episode_steps.reshape({b});
  const torch::Tensor actions = rollout.FlatActions();
  const torch::Tensor old_log_probs = rollout.log_probs.reshape({b});
  const torch::Tensor windows =
      InferenceWindows(rollout.obs, rollout.ended, config_.inference_window);
  const torch::Tensor all_tasks = torch::eye(num_tasks, torch::kFloat32);

  Metrics metrics;
  torch::Tensor noise, x_value;
  {
    torch::NoGradGuard no_grad;
    // the sampling noise of each step's latent under the encoder that drew it
    const nn::ActionDistribution enc = encoder_->Forward(all_tasks);
    noise = (latent - enc.mean.index_select(0, tasks)) *
            torch::exp(-enc.log_std.index_select(0, tasks));
    x_value = BaselineInput(obs, one_hot, latent);
    rollout.values.copy_(Values(x_value, t).reshape(rollout.values.sizes()));
    const torch::Tensor final_x =
        BaselineInput(rollout.final_obs.reshape({b, spaces_.obs_dim}), one_hot, latent);
    const torch::Tensor boot = Values(final_x, t + 1).reshape(rollout.values.sizes());
    rollout.bootstrap_values.copy_(boot * rollout.ended * (1.0 - rollout.terminated));
  }

  // 1. the augmented rewards
  const torch::Tensor raw_rewards = rollout.rewards.clone();
  {
    torch::NoGradGuard no_grad;
    const torch::Tensor ce = SoftplusIf(
        config_.softplus_entropy, (-inference_->Forward(windows).LogProb(latent)).clamp(-3.0, 3.0));
    torch::Tensor bonus = -config_.inference_ce_coeff * ce;
    if (config_.entropy_method == "max") {
      bonus = bonus + config_.entropy_coeff * SoftplusIf(config_.softplus_entropy, -old_log_probs);
    }
    rollout.rewards.add_(bonus.reshape(rollout.rewards.sizes()));
    metrics.Set("inference_ce", ce.mean().item<double>());
    metrics.Set("reward_bonus", bonus.mean().item<double>());
  }
  // 2. advantages
  RequireFinite(rollout.values, "te_ppo", "the baseline's values");
  RequireFinite(rollout.bootstrap_values, "te_ppo", "the baseline's values");
  RequireFinite(rollout.rewards, "te_ppo", "the augmented rewards");
  rollout.ComputeAdvantages(config_.discount, config_.gae_lambda);
  if (linear_) linear_->Fit(x_value, t, rollout.DiscountedReturns(config_.discount).reshape({b}));
  rollout.rewards.copy_(raw_rewards);
  const torch::Tensor returns = rollout.returns.reshape({b});
  torch::Tensor adv = rollout.advantages.reshape({b});
  if (config_.center_advantages && b > 1) adv = (adv - adv.mean()) / (adv.std() + 1e-8);
  metrics.Set("explained_variance", ExplainedVariance(rollout.values.reshape({b}), returns));

  // 3. policy and encoder
  const double regularizer = config_.entropy_method == "regularized" ? config_.entropy_coeff : 0.0;
  const int64_t mb = std::min(config_.minibatch_size, b);
  ClippedEpochSums sums;
  double value_loss = 0, enc_entropy = 0;
  for (int64_t e = 0; e < config_.epochs; ++e) {
    sums = {};
    value_loss = enc_entropy = 0;
    const torch::Tensor perm = torch::randperm(b, generator_, torch::kInt64);
    for (int64_t lo = 0; lo < b; lo += mb) {
      const torch::Tensor rows = perm.narrow(0, lo, std::min(mb, b - lo));
      const torch::Tensor row_tasks = tasks.index_select(0, rows);
      const nn::ActionDistribution enc = encoder_->Forward(all_tasks);
      const torch::Tensor z =
          enc.mean.index_select(0, row_tasks) +
          torch::exp(enc.log_std.index_select(0, row_tasks)) * noise.index_select(0, rows);
      const nn::ActionDistribution d =
          policy_->Forward(torch::cat({obs.index_select(0, rows), z}, -1));
      const ClippedSurrogate surrogate = ClippedSurrogateLoss(
          d.LogProb(actions.index_select(0, rows)), old_log_probs.index_select(0, rows),
          adv.index_select(0, rows), config_.clip_range);
      const torch::Tensor ent = d.Entropy().mean();
      const torch::Tensor task_entropy = (enc.log_std + kLogSqrt2PiE).sum(-1).mean();
      const torch::Tensor loss =
          surrogate.loss - regularizer * ent - config_.encoder_entropy_coeff * task_entropy;
      policy_->ZeroGrad();
      encoder_->ZeroGrad();
      loss.backward();
      ClipGradNorm(policy_->flat_grad(), config_.max_grad_norm);
      policy_optimizer_.Step(policy_->flat(), policy_->flat_grad());
      encoder_optimizer_.Step(encoder_->flat(), encoder_->flat_grad());
      sums.Add(loss, ent, surrogate);
      enc_entropy += task_entropy.item<double>();
      if (value_) {
        const torch::Tensor v = value_->Forward(x_value.index_select(0, rows));
        const torch::Tensor vloss = (v - returns.index_select(0, rows)).square().mean();
        value_->ZeroGrad();
        vloss.backward();
        value_optimizer_.Step(value_->flat(), value_->flat_grad());
        value_loss += vloss.item<double>();
      }
    }
  }
  RequireFinite(policy_->flat(), "te_ppo", "the policy's parameters");
  if (sums.count > 0) {
    const auto count = static_cast<double>(sums.count);
    metrics.Set("policy_loss", sums.policy_loss / count);
    if (value_) metrics.Set("value_loss", value_loss / count);
    metrics.Set("entropy", sums.entropy / count);
    metrics.Set("encoder_entropy", enc_entropy / count);
    metrics.Set("approx_kl", sums.approx_kl / count);
    metrics.Set("clip_fraction", sums.clip_fraction / count);
  }

  // 4. inference network: discounted maximum likelihood of the episode latents
  const torch::Tensor weights = torch::pow(config_.discount, t);
  const int64_t imb = std::min(config_.inference_minibatch_size, b);
  double inference_loss = 0;
  int64_t inference_count = 0;
  for (int64_t e = 0; e < config_.inference_epochs; ++e) {
    inference_loss = 0;
    inference_count = 0;
    const torch::Tensor perm = torch::randperm(b, generator_, torch::kInt64);
    for (int64_t lo = 0; lo < b; lo += imb) {
      const torch::Tensor rows = perm.narrow(0, lo, std::min(imb, b - lo));
      const torch::Tensor ll =
          inference_->Forward(windows.index_select(0, rows)).LogProb(latent.index_select(0, rows));
      const torch::Tensor loss = -(weights.index_select(0, rows) * ll).mean();
      inference_->ZeroGrad();
      loss.backward();
      inference_optimizer_.Step(inference_->flat(), inference_->flat_grad());
      inference_loss += loss.item<double>();
      ++inference_count;
    }
  }
  if (inference_count > 0) metrics.Set("inference_loss", inference_loss / inference_count);
  {
    torch::NoGradGuard no_grad;
    const torch::Tensor error = inference_->Forward(windows).mean - latent;
    metrics.Set("inference_rmse", error.square().mean().sqrt().item<double>());
    if (num_tasks > 1) {
      // how far apart the tasks' latents are: the smallest distance between two means
      const torch::Tensor means = encoder_->Forward(all_tasks).mean;
      const torch::Tensor dist = torch::cdist(means.unsqueeze(0), means.unsqueeze(0)).squeeze(0);
      const torch::Tensor off_diagonal = dist + torch::eye(num_tasks) * 1e9;
      metrics.Set("latent_min_distance", off_diagonal.min().item<double>());
    }
  }
  ++num_updates_;
  return metrics;
}

template <typename Archive, typename Self>
void TePpoLearner::TransferNetworks(Archive& archive, Self& self) {
  Transfer(archive, "policy", *self.policy_);
  Transfer(archive, "encoder", *self.encoder_);
  Transfer(archive, "inference", *self.inference_);
  Transfer(archive, "policy_optimizer", self.policy_optimizer_);
  Transfer(archive, "encoder_optimizer", self.encoder_optimizer_);
  Transfer(archive, "inference_optimizer", self.inference_optimizer_);
  TransferBaseline(archive, self.value_, self.value_optimizer_, self.linear_);
}

void TePpoLearner::Save(torch::serialize::OutputArchive& archive) const {
  // the key names the algorithm; PPO and TRPO checkpoints do not have it
  archive.write("te_ppo_latent_dim", torch::tensor(config_.latent_dim, torch::kInt64));
  archive.write("num_tasks", torch::tensor(spaces_.num_tasks, torch::kInt64));
  TransferNetworks(archive, *this);
  WriteProgress(archive, num_updates_, generator_);
}

void TePpoLearner::Load(torch::serialize::InputArchive& archive) {
  torch::Tensor latent_dim, num_tasks;
  if (!archive.try_read("te_ppo_latent_dim", latent_dim) ||
      !archive.try_read("num_tasks", num_tasks) ||
      latent_dim.item<int64_t>() != config_.latent_dim ||
      num_tasks.item<int64_t>() != spaces_.num_tasks) {
    throw Error("te_ppo checkpoint: not a TE-PPO checkpoint with latent_dim " +
                std::to_string(config_.latent_dim) + " and " + std::to_string(spaces_.num_tasks) +
                " tasks");
  }
  TransferNetworks(archive, *this);
  ReadProgress(archive, num_updates_, generator_);
}

}  // namespace manyworlds::agents
