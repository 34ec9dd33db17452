#include "manyworlds/agents/sac.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/pcgrad.h"
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

int64_t ArchCode(const std::string& architecture) {
  const std::vector<std::string>& names = SacArchitectures();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == architecture) return static_cast<int64_t>(i);
  }
  throw ConfigError("SacConfig.architecture: unknown '" + architecture + "'");
}

// Throws Error unless task_index is a (B) int64 tensor with values in [0, n).
void CheckTaskIndex(const torch::Tensor& task_index, int64_t b, int64_t n, const char* what) {
  if (!task_index.defined() || task_index.dim() != 1 || task_index.size(0) != b ||
      task_index.scalar_type() != torch::kInt64) {
    throw Error(std::string(what) + ": task_index must be an int64 tensor of shape (" +
                std::to_string(b) + ")");
  }
  auto [lo, hi] = torch::aminmax(task_index);
  if (lo.item<int64_t>() < 0 || hi.item<int64_t>() >= n) {
    throw Error(std::string(what) + ": task indices must lie in [0, " + std::to_string(n) +
                "), got [" + std::to_string(lo.item<int64_t>()) + ", " +
                std::to_string(hi.item<int64_t>()) + "]");
  }
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
      arch_(static_cast<Arch>(ArchCode(config.architecture))),
      obs_dim_(obs_dim),
      action_dim_(action_dim),
      num_tasks_(num_tasks),
      input_dim_(obs_dim),
      target_entropy_(config.target_entropy.value_or(-static_cast<double>(action_dim))),
      generator_(at::detail::createCPUGenerator(config.seed)),
      actor_optimizer_(0, Adam(config, config.actor_lr)),
      critic_optimizer_(0, Adam(config, config.critic_lr)),
      alpha_optimizer_(0, Adam(config, config.alpha_lr)),
      task_encoder_optimizer_(0, Adam(config, config.actor_lr)),
      encoder_optimizer_(0, Adam(config, config.critic_lr)) {
  if (obs_dim <= 0 || action_dim <= 0 || num_tasks <= 0) {
    throw ConfigError("SacLearner: obs_dim, action_dim and num_tasks must be > 0, got " +
                      std::to_string(obs_dim) + ", " + std::to_string(action_dim) + ", " +
                      std::to_string(num_tasks));
  }
  nn::ConfigureTorchThreads();

  // Encoders first (fixed order of draws from the generator: task encoder,
  // mixture encoder, actor, critics).
  const int64_t embed = config.task_embedding_dim;
  if (arch_ == Arch::kTaskEncoder || arch_ == Arch::kMoe) {
    nn::TaskEncoderOptions task;
    task.num_tasks = num_tasks;
    task.embedding_dim = embed;
    task.hidden_dim = embed;
    task.output_dim = embed;
    task_encoder_ = nn::TaskEncoder(task, generator_);
    task_encoder_optimizer_ =
        nn::FlatAdam(task_encoder_->num_params(), Adam(config, config.actor_lr));
  }
  int64_t heads = 1;
  switch (arch_) {
    case Arch::kMlp:
      if (num_tasks > 1) input_dim_ = obs_dim + num_tasks;
      break;
    case Arch::kMultiHead:
      heads = num_tasks;
      break;
    case Arch::kTaskEncoder:
      input_dim_ = obs_dim + embed;
      break;
    case Arch::kMoe: {
      nn::MixtureEncoderOptions moe;
      moe.input_dim = obs_dim;
      moe.context_dim = embed;
      moe.output_dim = config.encoder_dim;
      moe.hidden_dim = config.encoder_dim;
      moe.num_experts = config.num_experts;
      moe.selector_hidden_dim = embed;
      encoder_ = nn::MixtureEncoder(moe, generator_);
      encoder_target_ = nn::MixtureEncoder(moe, generator_);
      encoder_target_->CopyFrom(*encoder_);
      for (const torch::Tensor& p : encoder_target_->params()) p.requires_grad_(false);
      encoder_optimizer_ = nn::FlatAdam(encoder_->num_params(), Adam(config, config.critic_lr));
      input_dim_ = config.encoder_dim + embed;
      break;
    }
  }

  nn::GaussianPolicyOptions actor;
  actor.obs_dim = input_dim_;
  actor.action_dim = action_dim;
  actor.hidden_dim = config.hidden_dim;
  actor.num_layers = config.num_layers;
  actor.log_std_min = config.log_std_min;
  actor.log_std_max = config.log_std_max;
  actor.num_heads = heads;
  actor_ = nn::GaussianPolicy(actor, generator_);

  nn::TwinCriticOptions critic;
  critic.obs_dim = input_dim_;
  critic.action_dim = action_dim;
  critic.hidden_dim = config.hidden_dim;
  critic.num_layers = config.num_layers;
  critic.num_heads = heads;
  critic_ = nn::TwinCritic(critic, generator_);

  log_alpha_ = torch::full({config.disentangled_alpha ? num_tasks : 1},
                           std::log(config.init_temperature), torch::kFloat32);
  actor_optimizer_ = nn::FlatAdam(actor_->trunk()->num_params(), Adam(config, config.actor_lr));
  critic_optimizer_ =
      nn::FlatAdam(critic_->online()->num_params(), Adam(config, config.critic_lr));
  alpha_optimizer_ = nn::FlatAdam(log_alpha_.numel(), Adam(config, config.alpha_lr));
}

std::vector<std::pair<nn::FlatModule*, nn::FlatAdam*>> SacLearner::CriticGroup() {
  std::vector<std::pair<nn::FlatModule*, nn::FlatAdam*>> group = {
      {critic_->online().get(), &critic_optimizer_}};
  if (encoder_) group.emplace_back(encoder_.get(), &encoder_optimizer_);
  if (task_encoder_) group.emplace_back(task_encoder_.get(), &task_encoder_optimizer_);
  return group;
}

torch::Tensor SacLearner::NetworkInput(const torch::Tensor& obs, const torch::Tensor& task_index,
                                       bool target) const {
  switch (arch_) {
    case Arch::kMlp:
      if (num_tasks_ == 1) return obs;
      return torch::cat({obs, torch::one_hot(task_index, num_tasks_).to(obs.scalar_type())}, -1);
    case Arch::kMultiHead:
      return obs;
    case Arch::kTaskEncoder:
      return torch::cat(
          {obs, task_encoder_->Encode(task_encoder_->params()).index_select(0, task_index)}, -1);
    case Arch::kMoe: {
      // All task encodings (num_tasks, E) and mixture weights (num_tasks, K)
      // are tiny; rows are picked per sample. The selector reads the task
      // encoding detached (MTRL's should_detach_task_encoding).
      const torch::Tensor z = task_encoder_->Encode(task_encoder_->params());
      const nn::MixtureEncoder& moe = target ? encoder_target_ : encoder_;
      const std::vector<torch::Tensor>& params =
          target ? moe->detached_params() : moe->params();
      const torch::Tensor weights = moe->Weights(z.detach(), params).index_select(0, task_index);
      return torch::cat({moe->Mix(obs, weights, params), z.index_select(0, task_index)}, -1);
    }
  }
  throw Error("SacLearner: unknown architecture");
}

torch::Tensor SacLearner::Heads(const torch::Tensor& task_index) const {
  return arch_ == Arch::kMultiHead ? task_index : torch::Tensor();
}

torch::Tensor SacLearner::SampleAlpha(const torch::Tensor& task_index) const {
  torch::Tensor alpha = log_alpha_.exp();
  return config_.disentangled_alpha ? alpha.index_select(0, task_index) : alpha;
}

torch::Tensor SacLearner::CriticTargetWithAlpha(const Batch& batch, const torch::Tensor& alpha) {
  torch::NoGradGuard no_grad;
  const torch::Tensor heads = Heads(batch.task_index);
  const torch::Tensor actor_in = NetworkInput(batch.next_obs, batch.task_index);
  const torch::Tensor critic_in =
      arch_ == Arch::kMoe ? NetworkInput(batch.next_obs, batch.task_index, /*target=*/true)
                          : actor_in;
  nn::PolicyOutput next = actor_->forward(actor_in, heads);
  nn::SquashedSample sample = nn::SampleSquashedGaussian(next.mean, next.log_std, generator_);
  torch::Tensor q = critic_->TargetQ(critic_in, sample.action, heads);  // (2, B)
  return SoftTdTarget(batch.reward, batch.done, torch::minimum(q[0], q[1]), sample.log_prob,
                      alpha, config_.discount);
}

torch::Tensor SacLearner::CriticTarget(const Batch& batch) {
  ValidateBatch(batch, obs_dim_, action_dim_, num_tasks_);
  return CriticTargetWithAlpha(batch, SampleAlpha(batch.task_index));
}

double SacLearner::PcGradBackward(const torch::Tensor& per_sample,
                                  const torch::Tensor& task_index,
                                  const std::vector<nn::FlatModule*>& modules) {
  // Mean loss of each task present in the batch.
  const torch::Tensor counts = torch::bincount(task_index, {}, num_tasks_);
  const torch::Tensor present = counts.nonzero().squeeze(1);
  const torch::Tensor task_loss =
      torch::zeros({num_tasks_}, per_sample.options())
          .index_add(0, task_index, per_sample)
          .div(counts.clamp_min(1).to(per_sample.scalar_type()));
  int64_t total = 0;
  for (nn::FlatModule* m : modules) total += m->num_params();
  const int64_t t = present.size(0);
  torch::Tensor grads = torch::empty({t, total}, torch::kFloat32);
  const int64_t* tasks = present.data_ptr<int64_t>();
  for (int64_t i = 0; i < t; ++i) {
    for (nn::FlatModule* m : modules) m->ZeroGrad();
    task_loss[tasks[i]].backward({}, /*retain_graph=*/i + 1 < t);
    int64_t offset = 0;
    for (nn::FlatModule* m : modules) {
      grads[i].narrow(0, offset, m->num_params()).copy_(m->flat_grad());
      offset += m->num_params();
    }
  }
  const nn::PcGradResult combined = nn::ProjectConflictingGradients(grads, generator_);
  int64_t offset = 0;
  for (nn::FlatModule* m : modules) {
    m->flat_grad().copy_(combined.gradient.narrow(0, offset, m->num_params()));
    offset += m->num_params();
  }
  return combined.pairs > 0 ? static_cast<double>(combined.conflicts) / combined.pairs : 0.0;
}

Metrics SacLearner::Update(const Batch& batch) {
  ValidateBatch(batch, obs_dim_, action_dim_, num_tasks_);
  Metrics metrics;
  const torch::Tensor alpha = SampleAlpha(batch.task_index);  // (B) or (1), no grad
  const torch::Tensor heads = Heads(batch.task_index);

  // Critic (and the encoders it trains).
  const torch::Tensor target = CriticTargetWithAlpha(batch, alpha);
  const std::vector<std::pair<nn::FlatModule*, nn::FlatAdam*>> group = CriticGroup();
  const torch::Tensor critic_in = NetworkInput(batch.obs, batch.task_index);
  const torch::Tensor q = critic_->forward(critic_in, batch.action, heads);  // (2, B)
  // Mean over both critics times 2 = MSE(Q1, y) + MSE(Q2, y).
  const torch::Tensor critic_loss = 2.0 * (q - target).square().mean();
  const double critic_loss_value = critic_loss.item<double>();
  if (config_.max_critic_loss > 0.0 && !(critic_loss_value <= config_.max_critic_loss)) {
    throw Error("SAC critic loss " + std::to_string(critic_loss_value) + " exceeds " +
                "max_critic_loss " + std::to_string(config_.max_critic_loss) +
                " at update " + std::to_string(num_updates_) + " (diverged)");
  }
  if (config_.pcgrad) {
    std::vector<nn::FlatModule*> modules;
    for (const auto& [module, optimizer] : group) modules.push_back(module);
    const torch::Tensor per_sample = (q - target).square().sum(0);  // (B)
    metrics.Set("pcgrad_conflicts", PcGradBackward(per_sample, batch.task_index, modules));
  } else {
    for (const auto& [module, optimizer] : group) module->ZeroGrad();
    critic_loss.backward();
  }
  for (const auto& [module, optimizer] : group) {
    optimizer->Step(module->flat(), module->flat_grad());
  }
  metrics.Set("critic_loss", critic_loss_value);
  metrics.Set("q_mean", q.detach().mean().item<double>());

  // Actor and temperature, against the critics (and encoders) just updated.
  if (num_updates_ % config_.actor_update_freq == 0) {
    nn::MlpImpl& trunk = *actor_->trunk();
    torch::Tensor x;
    {
      torch::NoGradGuard no_grad;  // the actor sees encodings detached
      x = NetworkInput(batch.obs, batch.task_index);
    }
    const nn::PolicyOutput out = actor_->forward(x, heads);
    const nn::SquashedSample pi = nn::SampleSquashedGaussian(out.mean, out.log_std, generator_);
    const torch::Tensor q_pi =
        critic_->Q(x, pi.action, heads, critic_->online()->detached_params());
    const torch::Tensor per_sample = alpha * pi.log_prob - torch::minimum(q_pi[0], q_pi[1]);
    const torch::Tensor actor_loss = per_sample.mean();
    if (config_.pcgrad) {
      metrics.Set("pcgrad_actor_conflicts",
                  PcGradBackward(per_sample, batch.task_index, {&trunk}));
    } else {
      trunk.ZeroGrad();
      actor_loss.backward();
    }
    actor_optimizer_.Step(trunk.flat(), trunk.flat_grad());

    // d/dlog_alpha of mean_b(alpha_b (-log_prob_b - target)) is alpha_b (...)
    // summed per temperature and divided by B.
    const torch::Tensor log_prob = pi.log_prob.detach();
    const torch::Tensor per_sample_alpha = alpha * (-log_prob - target_entropy_);  // (B)
    const int64_t b = batch.size();
    torch::Tensor alpha_grad =
        config_.disentangled_alpha
            ? torch::zeros_like(log_alpha_).index_add_(0, batch.task_index, per_sample_alpha) / b
            : per_sample_alpha.mean().reshape({1});
    alpha_optimizer_.Step(log_alpha_, alpha_grad);

    metrics.Set("actor_loss", actor_loss.item<double>());
    metrics.Set("alpha", alpha.mean().item<double>());
    metrics.Set("alpha_loss", per_sample_alpha.mean().item<double>());
    metrics.Set("entropy", -log_prob.mean().item<double>());
  }

  if (num_updates_ % config_.critic_target_update_freq == 0) {
    critic_->UpdateTarget(config_.tau);
    if (encoder_) nn::PolyakUpdate(encoder_target_->flat(), encoder_->flat(), config_.tau);
  }
  ++num_updates_;
  return metrics;
}

torch::Tensor SacLearner::Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                              bool deterministic) {
  c10::InferenceMode inference;
  const bool single = obs.dim() == 1;
  const torch::Tensor x = single ? obs.unsqueeze(0) : obs;
  if (x.dim() != 2 || x.size(1) != obs_dim_) {
    throw Error("SacLearner::Act: obs must be (B, " + std::to_string(obs_dim_) + ") or (" +
                std::to_string(obs_dim_) + ")");
  }
  const torch::Tensor task = single && task_index.defined() ? task_index.reshape({-1})
                                                            : task_index;
  CheckTaskIndex(task, x.size(0), num_tasks_, "SacLearner::Act");
  const torch::Tensor heads = Heads(task);
  const nn::PolicyOutput out =
      actor_->forward(NetworkInput(x.to(torch::kFloat32), task), heads);
  torch::Tensor action = deterministic
                             ? torch::tanh(out.mean)
                             : nn::SampleSquashedGaussian(out.mean, out.log_std, generator_).action;
  return single ? action.squeeze(0) : action;
}

torch::Tensor SacLearner::Act(const torch::Tensor& obs, bool deterministic) {
  if (num_tasks_ != 1) {
    throw Error("SacLearner::Act(obs, deterministic) is for single-task learners; this one has " +
                std::to_string(num_tasks_) + " tasks: call Act(obs, task_index, deterministic)");
  }
  const int64_t b = obs.dim() == 2 ? obs.size(0) : 1;
  return Act(obs, torch::zeros({b}, torch::kInt64), deterministic);
}

void SacLearner::Save(torch::serialize::OutputArchive& archive) const {
  archive.write("architecture", torch::tensor(static_cast<int64_t>(arch_), torch::kInt64));
  archive.write("num_tasks", torch::tensor(num_tasks_, torch::kInt64));
  WriteModule(archive, "actor", *actor_->trunk());
  WriteModule(archive, "critic", *critic_->online());
  WriteModule(archive, "critic_target", *critic_->target());
  archive.write("log_alpha", log_alpha_);
  WriteOptimizer(archive, "actor_optimizer", actor_optimizer_);
  WriteOptimizer(archive, "critic_optimizer", critic_optimizer_);
  WriteOptimizer(archive, "alpha_optimizer", alpha_optimizer_);
  if (task_encoder_) {
    WriteModule(archive, "task_encoder", *task_encoder_);
    WriteOptimizer(archive, "task_encoder_optimizer", task_encoder_optimizer_);
  }
  if (encoder_) {
    WriteModule(archive, "encoder", *encoder_);
    WriteModule(archive, "encoder_target", *encoder_target_);
    WriteOptimizer(archive, "encoder_optimizer", encoder_optimizer_);
  }
  archive.write("num_updates", torch::tensor(num_updates_, torch::kInt64));
  archive.write("generator", generator_.get_state());
}

void SacLearner::Load(torch::serialize::InputArchive& archive) {
  torch::Tensor arch, tasks;
  if (!archive.try_read("architecture", arch) || !archive.try_read("num_tasks", tasks)) {
    throw Error("SacLearner::Load: not a SAC checkpoint of this version (no architecture)");
  }
  const std::vector<std::string>& names = SacArchitectures();
  const int64_t code = arch.item<int64_t>();
  if (code != static_cast<int64_t>(arch_) || tasks.item<int64_t>() != num_tasks_) {
    const std::string saved = code >= 0 && code < static_cast<int64_t>(names.size())
                                  ? names[static_cast<size_t>(code)]
                                  : "unknown";
    throw Error("SacLearner::Load: checkpoint is architecture '" + saved + "' with " +
                std::to_string(tasks.item<int64_t>()) + " tasks, this learner '" +
                config_.architecture + "' with " + std::to_string(num_tasks_));
  }
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
  if (task_encoder_) {
    ReadModule(archive, "task_encoder", *task_encoder_);
    ReadOptimizer(archive, "task_encoder_optimizer", task_encoder_optimizer_);
  }
  if (encoder_) {
    ReadModule(archive, "encoder", *encoder_);
    ReadModule(archive, "encoder_target", *encoder_target_);
    ReadOptimizer(archive, "encoder_optimizer", encoder_optimizer_);
  }
  archive.read("num_updates", num_updates);
  num_updates_ = num_updates.item<int64_t>();
  archive.read("generator", generator_state);
  generator_.set_state(generator_state);
}

}  // namespace manyworlds::agents
