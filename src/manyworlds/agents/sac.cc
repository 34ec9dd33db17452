#include "manyworlds/agents/sac.h"

#include <cmath>
#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/threads.h"

namespace manyworlds::agents {
namespace {

nn::AdamOptions Adam(const SacConfig& config, double lr) {
  nn::AdamOptions options;
  options.lr = lr;
  options.beta1 = config.adam_beta1;
  options.beta2 = config.adam_beta2;
  return options;
}

const SacConfig& Validated(const SacConfig& config) {
  config.Validate();
  return config;
}

void WriteModule(torch::serialize::OutputArchive& archive, const char* key,
                 const torch::nn::Module& module) {
  torch::serialize::OutputArchive sub;
  module.save(sub);
  archive.write(key, sub);
}

void ReadModule(torch::serialize::InputArchive& archive, const char* key,
                torch::nn::Module& module) {
  torch::serialize::InputArchive sub;
  archive.read(key, sub);
  module.load(sub);
}

void WriteOptimizer(torch::serialize::OutputArchive& archive, const char* key,
                    const nn::FlatAdam& optimizer) {
  torch::serialize::OutputArchive sub;
  optimizer.Save(sub);
  archive.write(key, sub);
}

void ReadOptimizer(torch::serialize::InputArchive& archive, const char* key,
                   nn::FlatAdam& optimizer) {
  torch::serialize::InputArchive sub;
  archive.read(key, sub);
  optimizer.Load(sub);
}

}  // namespace

torch::Tensor SoftTdTarget(const torch::Tensor& reward, const torch::Tensor& done,
                           const torch::Tensor& next_q, const torch::Tensor& next_log_prob,
                           const torch::Tensor& alpha, double discount) {
  torch::Tensor not_done = 1.0 - done.to(reward.scalar_type());
  return reward + discount * not_done * (next_q - alpha * next_log_prob);
}

SacLearner::SacLearner(const SacConfig& config, int64_t obs_dim, int64_t action_dim,
                       int64_t num_tasks)
    : config_(Validated(config)),
      obs_dim_(obs_dim),
      action_dim_(action_dim),
      num_tasks_(num_tasks),
      target_entropy_(config.target_entropy.value_or(-static_cast<double>(action_dim))),
      generator_(at::detail::createCPUGenerator(config.seed)),
      actor_optimizer_(0, Adam(config, config.actor_lr)),
      critic_optimizer_(0, Adam(config, config.critic_lr)),
      alpha_optimizer_(0, Adam(config, config.alpha_lr)) {
  if (obs_dim <= 0 || action_dim <= 0 || num_tasks <= 0) {
    throw ConfigError("SacLearner: obs_dim, action_dim and num_tasks must be > 0, got " +
                      std::to_string(obs_dim) + ", " + std::to_string(action_dim) + ", " +
                      std::to_string(num_tasks));
  }
  nn::ConfigureTorchThreads();

  nn::GaussianPolicyOptions actor;
  actor.obs_dim = obs_dim;
  actor.action_dim = action_dim;
  actor.hidden_dim = config.hidden_dim;
  actor.num_layers = config.num_layers;
  actor.log_std_min = config.log_std_min;
  actor.log_std_max = config.log_std_max;
  actor_ = nn::GaussianPolicy(actor, generator_);

  nn::TwinCriticOptions critic;
  critic.obs_dim = obs_dim;
  critic.action_dim = action_dim;
  critic.hidden_dim = config.hidden_dim;
  critic.num_layers = config.num_layers;
  critic_ = nn::TwinCritic(critic, generator_);

  log_alpha_ = torch::full({config.disentangled_alpha ? num_tasks : 1},
                           std::log(config.init_temperature), torch::kFloat32);
  actor_optimizer_ = nn::FlatAdam(actor_->trunk()->num_params(), Adam(config, config.actor_lr));
  critic_optimizer_ =
      nn::FlatAdam(critic_->online()->num_params(), Adam(config, config.critic_lr));
  alpha_optimizer_ = nn::FlatAdam(log_alpha_.numel(), Adam(config, config.alpha_lr));
}

torch::Tensor SacLearner::SampleAlpha(const torch::Tensor& task_index) const {
  torch::Tensor alpha = log_alpha_.exp();
  return config_.disentangled_alpha ? alpha.index_select(0, task_index) : alpha;
}

torch::Tensor SacLearner::CriticTargetWithAlpha(const Batch& batch, const torch::Tensor& alpha) {
  torch::NoGradGuard no_grad;
  nn::PolicyOutput next = actor_->forward(batch.next_obs);
  nn::SquashedSample sample = nn::SampleSquashedGaussian(next.mean, next.log_std, generator_);
  torch::Tensor q = critic_->TargetQ(batch.next_obs, sample.action);  // (2, B)
  return SoftTdTarget(batch.reward, batch.done, torch::minimum(q[0], q[1]), sample.log_prob,
                      alpha, config_.discount);
}

torch::Tensor SacLearner::CriticTarget(const Batch& batch) {
  ValidateBatch(batch, obs_dim_, action_dim_, num_tasks_);
  return CriticTargetWithAlpha(batch, SampleAlpha(batch.task_index));
}

Metrics SacLearner::Update(const Batch& batch) {
  ValidateBatch(batch, obs_dim_, action_dim_, num_tasks_);
  Metrics metrics;
  const torch::Tensor alpha = SampleAlpha(batch.task_index);  // (B) or (1), no grad

  // Critic.
  const torch::Tensor target = CriticTargetWithAlpha(batch, alpha);
  nn::EnsembleMlpImpl& online = *critic_->online();
  const torch::Tensor q = critic_->forward(batch.obs, batch.action);  // (2, B)
  // Mean over both critics times 2 = MSE(Q1, y) + MSE(Q2, y).
  const torch::Tensor critic_loss = 2.0 * (q - target).square().mean();
  const double critic_loss_value = critic_loss.item<double>();
  if (config_.max_critic_loss > 0.0 && !(critic_loss_value <= config_.max_critic_loss)) {
    throw Error("SAC critic loss " + std::to_string(critic_loss_value) + " exceeds " +
                "max_critic_loss " + std::to_string(config_.max_critic_loss) +
                " at update " + std::to_string(num_updates_) + " (diverged)");
  }
  online.ZeroGrad();
  critic_loss.backward();
  critic_optimizer_.Step(online.flat(), online.flat_grad());
  metrics.Set("critic_loss", critic_loss_value);
  metrics.Set("q_mean", q.detach().mean().item<double>());

  // Actor and temperature, against the critics just updated.
  if (num_updates_ % config_.actor_update_freq == 0) {
    nn::MlpImpl& trunk = *actor_->trunk();
    const nn::PolicyOutput out = actor_->forward(batch.obs);
    const nn::SquashedSample pi = nn::SampleSquashedGaussian(out.mean, out.log_std, generator_);
    const torch::Tensor q_pi = critic_->Q(batch.obs, pi.action, online.detached_params());
    const torch::Tensor actor_loss =
        (alpha * pi.log_prob - torch::minimum(q_pi[0], q_pi[1])).mean();
    trunk.ZeroGrad();
    actor_loss.backward();
    actor_optimizer_.Step(trunk.flat(), trunk.flat_grad());

    // d/dlog_alpha of mean_b(alpha_b (-log_prob_b - target)) is alpha_b (...)
    // summed per temperature and divided by B.
    const torch::Tensor log_prob = pi.log_prob.detach();
    const torch::Tensor per_sample = alpha * (-log_prob - target_entropy_);  // (B)
    const int64_t b = batch.size();
    torch::Tensor alpha_grad =
        config_.disentangled_alpha
            ? torch::zeros_like(log_alpha_).index_add_(0, batch.task_index, per_sample) / b
            : per_sample.mean().reshape({1});
    alpha_optimizer_.Step(log_alpha_, alpha_grad);

    metrics.Set("actor_loss", actor_loss.item<double>());
    metrics.Set("alpha", alpha.mean().item<double>());
    metrics.Set("alpha_loss", per_sample.mean().item<double>());
    metrics.Set("entropy", -log_prob.mean().item<double>());
  }

  if (num_updates_ % config_.critic_target_update_freq == 0) critic_->UpdateTarget(config_.tau);
  ++num_updates_;
  return metrics;
}

torch::Tensor SacLearner::Act(const torch::Tensor& obs, bool deterministic) {
  c10::InferenceMode inference;
  const bool single = obs.dim() == 1;
  const torch::Tensor x = single ? obs.unsqueeze(0) : obs;
  if (x.dim() != 2 || x.size(1) != obs_dim_) {
    throw Error("SacLearner::Act: obs must be (B, " + std::to_string(obs_dim_) + ") or (" +
                std::to_string(obs_dim_) + ")");
  }
  const nn::PolicyOutput out = actor_->forward(x.to(torch::kFloat32));
  torch::Tensor action = deterministic
                             ? torch::tanh(out.mean)
                             : nn::SampleSquashedGaussian(out.mean, out.log_std, generator_).action;
  return single ? action.squeeze(0) : action;
}

void SacLearner::Save(torch::serialize::OutputArchive& archive) const {
  WriteModule(archive, "actor", *actor_->trunk());
  WriteModule(archive, "critic", *critic_->online());
  WriteModule(archive, "critic_target", *critic_->target());
  archive.write("log_alpha", log_alpha_);
  WriteOptimizer(archive, "actor_optimizer", actor_optimizer_);
  WriteOptimizer(archive, "critic_optimizer", critic_optimizer_);
  WriteOptimizer(archive, "alpha_optimizer", alpha_optimizer_);
  archive.write("num_updates", torch::tensor(num_updates_, torch::kInt64));
  archive.write("generator", generator_.get_state());
}

void SacLearner::Load(torch::serialize::InputArchive& archive) {
  ReadModule(archive, "actor", *actor_->trunk());
  ReadModule(archive, "critic", *critic_->online());
  ReadModule(archive, "critic_target", *critic_->target());
  torch::Tensor log_alpha, num_updates, generator_state;
  archive.read("log_alpha", log_alpha);
  if (log_alpha.numel() != log_alpha_.numel()) {
    throw Error("SacLearner::Load: checkpoint has " + std::to_string(log_alpha.numel()) +
                " temperatures, this learner " + std::to_string(log_alpha_.numel()));
  }
  log_alpha_.copy_(log_alpha.reshape({-1}));
  ReadOptimizer(archive, "actor_optimizer", actor_optimizer_);
  ReadOptimizer(archive, "critic_optimizer", critic_optimizer_);
  ReadOptimizer(archive, "alpha_optimizer", alpha_optimizer_);
  archive.read("num_updates", num_updates);
  num_updates_ = num_updates.item<int64_t>();
  archive.read("generator", generator_state);
  generator_.set_state(generator_state);
}

}  // namespace manyworlds::agents
