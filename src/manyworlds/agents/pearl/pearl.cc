#include "manyworlds/agents/pearl/pearl.h"

#include <cmath>
#include <limits>
#include <string>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/threads.h"
#include "manyworlds/rl/generator.h"

namespace manyworlds::agents {
namespace {

// Names of this actor's ActorState entries.
constexpr char kPearlLatent[] = "latent";
constexpr char kPearlContext[] = "context";
constexpr char kPearlHistory[] = "history";

constexpr int64_t kPearlCheckpointCode = 0x706561726c;  // "pearl"
// Seeds the generator every actor state draws from unless a protocol sets its own.
constexpr uint64_t kActorStream = 0x6163746f72;  // "actor"

nn::AdamOptions Adam(double lr) {
  nn::AdamOptions o;
  o.lr = lr;
  return o;
}

// Rows of `fresh` where mask (N) is true, else rows of `old`.
torch::Tensor WhereRows(const torch::Tensor& mask, const torch::Tensor& fresh,
                        const torch::Tensor& old) {
  return torch::where(mask.to(torch::kBool).unsqueeze(1), fresh, old);
}

}  // namespace

void PearlConfig::Validate() const {
  RequireField(latent_dim >= 1 && latent_dim <= 4096, "latent_dim", "in [1, 4096]", latent_dim);
  RequireField(hidden_dim >= 1 && hidden_dim <= 65536, "hidden_dim", "in [1, 65536]", hidden_dim);
  RequireField(num_layers >= 0 && num_layers <= 64, "num_layers", "in [0, 64]", num_layers);
  RequireField(encoder_hidden_dim >= 1 && encoder_hidden_dim <= 65536, "encoder_hidden_dim",
               "in [1, 65536]", encoder_hidden_dim);
  RequireField(encoder_num_layers >= 0 && encoder_num_layers <= 64, "encoder_num_layers",
               "in [0, 64]", encoder_num_layers);
  RequireField(FinitePositive(policy_lr), "policy_lr", "finite and > 0", policy_lr);
  RequireField(FinitePositive(qf_lr), "qf_lr", "finite and > 0", qf_lr);
  RequireField(FinitePositive(vf_lr), "vf_lr", "finite and > 0", vf_lr);
  RequireField(FinitePositive(context_lr), "context_lr", "finite and > 0", context_lr);
  RequireField(discount >= 0 && discount <= 1, "discount", "in [0, 1]", discount);
  RequireField(tau >= 0 && tau <= 1, "tau", "in [0, 1]", tau);
  RequireField(FinitePositive(reward_scale), "reward_scale", "finite and > 0", reward_scale);
  RequireField(std::isfinite(kl_lambda) && kl_lambda >= 0, "kl_lambda", "finite and >= 0",
               kl_lambda);
  RequireField(std::isfinite(policy_mean_reg) && policy_mean_reg >= 0, "policy_mean_reg",
               "finite and >= 0", policy_mean_reg);
  RequireField(std::isfinite(policy_std_reg) && policy_std_reg >= 0, "policy_std_reg",
               "finite and >= 0", policy_std_reg);
  RequireField(
      std::isfinite(log_std_min) && std::isfinite(log_std_max) && log_std_min < log_std_max,
      "log_std_max", "finite and > log_std_min", log_std_max);
  RequireField(meta_batch >= 1 && meta_batch <= 100000, "meta_batch", "in [1, 100000]", meta_batch);
  RequireField(batch_size >= 1 && batch_size <= 1000000, "batch_size", "in [1, 1e6]", batch_size);
  RequireField(embedding_batch_size >= 1 && embedding_batch_size <= 1000000, "embedding_batch_size",
               "in [1, 1e6]", embedding_batch_size);
  RequireField(meta_batch * batch_size <= 4000000, "batch_size",
               "at most 4e6 / meta_batch (RL rows per update)", batch_size);
  RequireField(meta_batch * embedding_batch_size <= 4000000, "embedding_batch_size",
               "at most 4e6 / meta_batch (context rows per update)", embedding_batch_size);
  RequireField(updates_per_iteration >= 0 && updates_per_iteration <= 10000000,
               "updates_per_iteration", "in [0, 1e7]", updates_per_iteration);
  RequireField(prior_episodes >= 0 && prior_episodes <= 10000, "prior_episodes", "in [0, 10000]",
               prior_episodes);
  RequireField(posterior_episodes >= 0 && posterior_episodes <= 10000, "posterior_episodes",
               "in [0, 10000]", posterior_episodes);
  RequireField(extra_posterior_episodes >= 0 && extra_posterior_episodes <= 10000,
               "extra_posterior_episodes", "in [0, 10000]", extra_posterior_episodes);
  RequireField(episodes_per_iteration() >= 1, "prior_episodes",
               "such that prior + posterior + extra_posterior episodes >= 1", prior_episodes);
  RequireField(prior_episodes + posterior_episodes >= 1, "prior_episodes",
               "such that prior + posterior episodes >= 1 (the encoder needs data)",
               prior_episodes);
}

PearlLearner::PearlLearner(const PearlConfig& config, int64_t obs_dim, int64_t action_dim)
    : config_(Validated(config)),
      obs_dim_(obs_dim),
      action_dim_(action_dim),
      generator_(rl::MakeGenerator(config.seed)),
      encoder_optimizer_(0, Adam(config.context_lr)),
      policy_optimizer_(0, Adam(config.policy_lr)),
      critic_optimizer_(0, Adam(config.qf_lr)),
      value_optimizer_(0, Adam(config.vf_lr)) {
  if (obs_dim <= 0 || action_dim <= 0) {
    throw ConfigError("pearl: obs_dim and action_dim must be > 0, got " + std::to_string(obs_dim) +
                      " and " + std::to_string(action_dim));
  }
  nn::ConfigureTorchThreads();
  const int64_t z = config.latent_dim;
  // fixed order of draws from the generator: encoder, policy, critics, value
  nn::MlpOptions encoder;
  encoder.input_dim = context_dim();
  encoder.output_dim = config.use_information_bottleneck ? 2 * z : z;
  encoder.hidden_dim = config.encoder_hidden_dim;
  encoder.num_layers = config.encoder_num_layers;
  encoder_ = nn::Mlp(encoder, generator_);

  nn::GaussianPolicyOptions policy;
  policy.obs_dim = obs_dim + z;
  policy.action_dim = action_dim;
  policy.hidden_dim = config.hidden_dim;
  policy.num_layers = config.num_layers;
  policy.log_std_min = config.log_std_min;
  policy.log_std_max = config.log_std_max;
  policy_ = nn::GaussianPolicy(policy, generator_);

  nn::MlpOptions critic;
  critic.input_dim = obs_dim + action_dim + z;
  critic.output_dim = 1;
  critic.hidden_dim = config.hidden_dim;
  critic.num_layers = config.num_layers;
  critic.ensemble_size = 2;
  critic_ = nn::EnsembleMlp(critic, generator_);

  nn::MlpOptions value = critic;
  value.input_dim = obs_dim + z;
  value.ensemble_size = 1;
  value_ = nn::Mlp(value, generator_);
  value_target_ = nn::Mlp(value, generator_);
  value_target_->CopyFrom(*value_);
  for (const torch::Tensor& p : value_target_->params()) p.requires_grad_(false);

  encoder_optimizer_ = nn::FlatAdam(encoder_->num_params(), Adam(config.context_lr));
  policy_optimizer_ = nn::FlatAdam(policy_->trunk()->num_params(), Adam(config.policy_lr));
  critic_optimizer_ = nn::FlatAdam(critic_->num_params(), Adam(config.qf_lr));
  value_optimizer_ = nn::FlatAdam(value_->num_params(), Adam(config.vf_lr));
}

torch::Tensor PearlLearner::ContextRows(const Batch& batch) {
  return torch::cat({batch.obs, batch.action, batch.reward.reshape({-1, 1})}, 1);
}

LatentBelief PearlLearner::Prior(int64_t rows) const {
  return {torch::zeros({rows, config_.latent_dim}), torch::ones({rows, config_.latent_dim})};
}

LatentBelief PearlLearner::Posterior(const torch::Tensor& context,
                                     const torch::Tensor& weight) const {
  if (context.dim() != 3 || context.size(2) != context_dim()) {
    throw Error("pearl: context must be (groups, rows, " + std::to_string(context_dim()) +
                "), got " + c10::str(context.sizes()));
  }
  const int64_t m = context.size(0), c = context.size(1), z = config_.latent_dim;
  if (c == 0) return Prior(m);
  const torch::Tensor w =
      weight.defined() ? weight.to(torch::kFloat32).reshape({m, c, 1}) : torch::ones({m, c, 1});
  const torch::Tensor out =
      encoder_->Forward(context.reshape({m * c, -1}), encoder_->params()).reshape({m, c, -1});
  const torch::Tensor mu = out.narrow(2, 0, z);
  const torch::Tensor count = w.sum(1);  // (m, 1)
  const torch::Tensor has = count > 0;
  LatentBelief belief;
  if (config_.use_information_bottleneck) {
    // product of the per-transition Gaussians (rows with weight 0 drop out)
    const torch::Tensor precision =
        w / torch::nn::functional::softplus(out.narrow(2, z, z)).clamp_min(1e-7);
    const torch::Tensor total = precision.sum(1);  // (m, z)
    const torch::Tensor var = 1.0 / total.clamp_min(1e-30);
    belief.mean = torch::where(has, var * (mu * precision).sum(1), torch::zeros_like(var));
    belief.var = torch::where(has, var, torch::ones_like(var));
  } else {
    belief.mean = torch::where(has, (mu * w).sum(1) / count.clamp_min(1.0), torch::zeros({m, z}));
    belief.var = torch::zeros({m, z});
  }
  return belief;
}

torch::Tensor PearlLearner::SampleLatent(const LatentBelief& belief, at::Generator& generator) {
  c10::InferenceMode inference;
  return belief.mean + belief.var.sqrt() * torch::randn(belief.mean.sizes(), generator);
}

torch::Tensor PearlLearner::ActWithLatent(const torch::Tensor& obs, const torch::Tensor& latent,
                                          bool deterministic, at::Generator& generator) {
  if (obs.dim() != 2 || obs.size(1) != obs_dim_ || latent.dim() != 2 ||
      latent.size(0) != obs.size(0) || latent.size(1) != config_.latent_dim) {
    throw Error("pearl: act needs obs (N, " + std::to_string(obs_dim_) + ") and latents (N, " +
                std::to_string(config_.latent_dim) + "), got " + c10::str(obs.sizes()) + " and " +
                c10::str(latent.sizes()));
  }
  c10::InferenceMode inference;
  const torch::Tensor x = torch::cat({obs.to(torch::kFloat32), latent}, 1);
  if (deterministic) return policy_->MeanAction(x);
  return policy_->Sample(x, generator).action;
}

Metrics PearlLearner::Update(const Batch& context, const Batch& rl, int64_t num_tasks) {
  if (num_tasks < 1 || context.size() == 0 || rl.size() == 0 || context.size() % num_tasks != 0 ||
      rl.size() % num_tasks != 0) {
    throw Error("pearl: Update needs context and RL batches of whole tasks (" +
                std::to_string(num_tasks) + " tasks; got " + std::to_string(context.size()) +
                " context and " + std::to_string(rl.size()) + " RL rows)");
  }
  ValidateBatch(context, obs_dim_, action_dim_, std::numeric_limits<int64_t>::max());
  ValidateBatch(rl, obs_dim_, action_dim_, std::numeric_limits<int64_t>::max());
  const int64_t t = num_tasks, b = rl.size() / t, zd = config_.latent_dim;

  // 1. posterior per task and z by reparameterisation
  encoder_->ZeroGrad();
  critic_->ZeroGrad();
  const LatentBelief q = Posterior(ContextRows(context).reshape({t, context.size() / t, -1}));
  torch::Tensor z = q.mean;
  torch::Tensor kl = torch::zeros({});
  if (config_.use_information_bottleneck) {
    z = q.mean + q.var.sqrt() * torch::randn({t, zd}, generator_);
    kl = 0.5 * (q.var + q.mean.square() - 1.0 - q.var.log()).sum();
  }
  const torch::Tensor z_rows = z.repeat_interleave(b, 0);  // (t * b, zd)
  const torch::Tensor z_fixed = z_rows.detach();

  // 2. critics and encoder
  const torch::Tensor q_pred =
      critic_->Forward(torch::cat({rl.obs, rl.action, z_rows}, 1)).squeeze(-1);  // (2, t b)
  torch::Tensor y;
  {
    torch::NoGradGuard no_grad;
    const torch::Tensor next_v =
        value_target_->Forward(torch::cat({rl.next_obs, z_fixed}, 1)).squeeze(-1);
    const torch::Tensor done = rl.done.to(torch::kFloat32);
    y = rl.reward * config_.reward_scale + (1.0 - done) * config_.discount * next_v;
  }
  const torch::Tensor qf_loss = (q_pred - y.unsqueeze(0)).square().mean(1).sum();
  const torch::Tensor critic_loss = qf_loss + config_.kl_lambda * kl;
  const double qf_value = qf_loss.item<double>();
  const double kl_value = kl.item<double>();
  if (!std::isfinite(qf_value) || !std::isfinite(kl_value)) {
    throw Error("pearl: non-finite critic loss (" + std::to_string(qf_value) + ") or KL (" +
                std::to_string(kl_value) + ") at update " + std::to_string(num_updates_) +
                "; lower the learning rates or reward_scale");
  }
  critic_loss.backward();
  critic_optimizer_.Step(critic_->flat(), critic_->flat_grad());
  encoder_optimizer_.Step(encoder_->flat(), encoder_->flat_grad());

  // 3. value function on fresh actions, judged by the stepped critics
  const torch::Tensor policy_in = torch::cat({rl.obs, z_fixed}, 1);
  const nn::PolicyOutput out = policy_->forward(policy_in);
  const nn::SquashedSample sample = nn::SquashedGaussianFromNoise(
      out.mean, out.log_std, torch::randn(out.mean.sizes(), generator_));
  const torch::Tensor q_new = std::get<0>(
      critic_->Forward(torch::cat({rl.obs, sample.action, z_fixed}, 1), critic_->detached_params())
          .squeeze(-1)
          .min(0));
  value_->ZeroGrad();
  const torch::Tensor v_pred = value_->Forward(policy_in).squeeze(-1);
  const torch::Tensor vf_loss = (v_pred - (q_new - sample.log_prob).detach()).square().mean();
  const torch::Tensor policy_loss = (sample.log_prob - q_new).mean() +
                                    config_.policy_mean_reg * out.mean.square().mean() +
                                    config_.policy_std_reg * out.log_std.square().mean();
  const double vf_value = vf_loss.item<double>();
  const double policy_value = policy_loss.item<double>();
  if (!std::isfinite(vf_value) || !std::isfinite(policy_value)) {
    throw Error("pearl: non-finite value (" + std::to_string(vf_value) + ") or policy loss (" +
                std::to_string(policy_value) + ") at update " + std::to_string(num_updates_));
  }
  vf_loss.backward();
  value_optimizer_.Step(value_->flat(), value_->flat_grad());
  nn::PolyakUpdate(value_target_->flat(), value_->flat(), config_.tau);

  // 4. policy
  policy_->trunk()->ZeroGrad();
  policy_loss.backward();
  policy_optimizer_.Step(policy_->trunk()->flat(), policy_->trunk()->flat_grad());
  ++num_updates_;

  Metrics metrics;
  metrics.Set("qf_loss", qf_value);
  metrics.Set("vf_loss", vf_value);
  metrics.Set("policy_loss", policy_value);
  metrics.Set("kl_divergence", kl_value / static_cast<double>(t));
  metrics.Set("q_mean", q_pred.detach().mean().item<double>());
  metrics.Set("entropy", -sample.log_prob.detach().mean().item<double>());
  metrics.Set("z_mean_abs", q.mean.detach().abs().mean().item<double>());
  metrics.Set("z_var", q.var.detach().mean().item<double>());
  return metrics;
}

ActorState PearlLearner::Initial(int64_t num_envs) {
  c10::InferenceMode inference;
  ActorState state;
  const LatentBelief prior = Prior(num_envs);
  state.tensors[kPearlContext] = torch::cat({prior.mean, prior.var}, 1);
  state.tensors[kPearlLatent] = torch::full({num_envs, config_.latent_dim}, std::nan(""));
  state.generator = rl::MakeGenerator(config_.seed ^ kActorStream);
  return state;
}

ActOutput PearlLearner::Act(const torch::Tensor& obs, const torch::Tensor& /*task_index*/,
                            ActorState& state, ActMode mode) {
  if (!state.tensors[kPearlLatent].defined() ||
      state.tensors[kPearlLatent].size(0) != obs.size(0)) {
    throw Error("pearl: the actor state has " +
                std::to_string(state.tensors[kPearlLatent].defined()
                                   ? state.tensors[kPearlLatent].size(0)
                                   : 0) +
                " envs but obs has " + std::to_string(obs.size(0)) + " rows; call Initial");
  }
  at::Generator& generator = SamplingGenerator(state, generator_);
  {
    c10::InferenceMode inference;
    const torch::Tensor redraw = state.tensors[kPearlLatent].isnan().any(1);
    if (redraw.any().item<bool>()) {
      const int64_t z = config_.latent_dim;
      const LatentBelief belief{state.tensors[kPearlContext].narrow(1, 0, z),
                                state.tensors[kPearlContext].narrow(1, z, z)};
      state.tensors[kPearlLatent] =
          WhereRows(redraw, SampleLatent(belief, generator), state.tensors[kPearlLatent]);
    }
  }
  ActOutput out;
  out.action =
      ActWithLatent(obs, state.tensors[kPearlLatent], mode == ActMode::kDeterministic, generator);
  return out;
}

void PearlLearner::Reset(const torch::Tensor& envs, ResetScope scope, ActorState& state) {
  c10::InferenceMode inference;
  const torch::Tensor mask = envs.to(torch::kBool);
  state.tensors[kPearlLatent] =
      WhereRows(mask, torch::full_like(state.tensors[kPearlLatent], std::nan("")),
                state.tensors[kPearlLatent]);
  if (scope == ResetScope::kEpisode) return;
  const LatentBelief prior = Prior(mask.size(0));
  state.tensors[kPearlContext] =
      WhereRows(mask, torch::cat({prior.mean, prior.var}, 1), state.tensors[kPearlContext]);
  if (mask.all().item<bool>()) {
    state.lists[kPearlHistory].clear();
    return;
  }
  ForgetHistoryRows(state.lists[kPearlHistory], mask);
}

void PearlLearner::Observe(const StepOutcome& o, ActorState& state) {
  c10::InferenceMode inference;
  const int64_t n = o.obs.size(0);
  const torch::Tensor valid = o.valid.defined() ? o.valid : torch::ones({n});
  state.lists[kPearlHistory].push_back(
      torch::cat({o.obs.to(torch::kFloat32), o.action.reshape({n, -1}), o.reward.reshape({n, 1}),
                  valid.reshape({n, 1})},
                 1));
  // a new episode draws a new z from the current belief
  const torch::Tensor ended = (o.ended > 0.5).logical_and(valid > 0.5);
  state.tensors[kPearlLatent] =
      WhereRows(ended, torch::full_like(state.tensors[kPearlLatent], std::nan("")),
                state.tensors[kPearlLatent]);
}

void PearlLearner::Adapt(const torch::Tensor& envs, ActorState& state) {
  c10::InferenceMode inference;
  const torch::Tensor mask = envs.to(torch::kBool);
  const int64_t n = mask.size(0), d = context_dim();
  LatentBelief posterior = Prior(n);
  if (!state.lists[kPearlHistory].empty()) {
    const torch::Tensor rows = torch::stack(state.lists[kPearlHistory], 1);  // (n, steps, d + 1)
    posterior = Posterior(rows.narrow(2, 0, d), rows.select(2, d));
  }
  state.tensors[kPearlContext] =
      WhereRows(mask, torch::cat({posterior.mean, posterior.var}, 1), state.tensors[kPearlContext]);
  state.tensors[kPearlLatent] =
      WhereRows(mask, torch::full_like(state.tensors[kPearlLatent], std::nan("")),
                state.tensors[kPearlLatent]);
}

template <typename Archive, typename Self>
void PearlLearner::TransferNetworks(Archive& archive, Self& self) {
  Transfer(archive, "encoder", *self.encoder_);
  Transfer(archive, "policy", *self.policy_);
  Transfer(archive, "critic", *self.critic_);
  Transfer(archive, "value", *self.value_);
  Transfer(archive, "value_target", *self.value_target_);
  Transfer(archive, "encoder_optimizer", self.encoder_optimizer_);
  Transfer(archive, "policy_optimizer", self.policy_optimizer_);
  Transfer(archive, "critic_optimizer", self.critic_optimizer_);
  Transfer(archive, "value_optimizer", self.value_optimizer_);
}

void PearlLearner::Save(torch::serialize::OutputArchive& archive) const {
  WriteSignature(
      archive, kPearlCheckpointCode,
      {obs_dim_, action_dim_, config_.latent_dim, config_.hidden_dim, config_.encoder_hidden_dim});
  TransferNetworks(archive, *this);
  WriteProgress(archive, num_updates_, generator_);
}

void PearlLearner::Load(torch::serialize::InputArchive& archive) {
  if (!HasSignature(archive, kPearlCheckpointCode,
                    {obs_dim_, action_dim_, config_.latent_dim, config_.hidden_dim,
                     config_.encoder_hidden_dim})) {
    throw Error("pearl checkpoint: not a checkpoint of PEARL with these sizes");
  }
  TransferNetworks(archive, *this);
  ReadProgress(archive, num_updates_, generator_);
}

}  // namespace manyworlds::agents
