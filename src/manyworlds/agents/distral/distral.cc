#include "manyworlds/agents/distral/distral.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <utility>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"
#include "manyworlds/core/rng.h"

namespace manyworlds::agents {
namespace {

template <typename T>
void RequireDistral(bool ok, const char* field, const std::string& allowed, T value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "DistralConfig." << field << " must be " << allowed << ", got " << value;
  throw ConfigError(msg.str());
}

// KL(N(m1, s1) || N(m2, s2)) of diagonal Gaussians, summed over the last dim.
torch::Tensor DiagGaussianKl(const torch::Tensor& mean1, const torch::Tensor& log_std1,
                             const torch::Tensor& mean2, const torch::Tensor& log_std2) {
  const torch::Tensor var1 = (2.0 * log_std1).exp(), var2 = (2.0 * log_std2).exp();
  return (log_std2 - log_std1 + (var1 + (mean1 - mean2).square()) / (2.0 * var2) - 0.5).sum(-1);
}

// Rows of `batch` whose task is `task`, relabelled as task 0.
Batch TaskRows(const Batch& batch, const torch::Tensor& rows) {
  Batch part;
  part.obs = batch.obs.index_select(0, rows);
  part.action = batch.action.index_select(0, rows);
  part.reward = batch.reward.index_select(0, rows);
  part.next_obs = batch.next_obs.index_select(0, rows);
  part.done = batch.done.index_select(0, rows);
  part.task_index = torch::zeros({rows.size(0)}, torch::kInt64);
  return part;
}

}  // namespace

void DistralConfig::Validate() const {
  RequireDistral(std::isfinite(distral_alpha) && distral_alpha >= 0, "distral_alpha",
                 "finite and >= 0", distral_alpha);
  RequireDistral(FinitePositive(distilled_lr), "distilled_lr", "finite and > 0", distilled_lr);
  RequireDistral(act_with == "task" || act_with == "distilled", "act_with", "'task' or 'distilled'",
                 "'" + act_with + "'");
  try {
    TaskAgentConfig(0).Validate();
  } catch (const ConfigError& e) {
    // Name this config, not the SAC one it fills.
    std::string msg = e.what();
    const std::string from = "SacConfig.";
    if (msg.rfind(from, 0) == 0) msg = "DistralConfig." + msg.substr(from.size());
    throw ConfigError(msg);
  }
}

SacConfig DistralConfig::TaskAgentConfig(int64_t task) const {
  SacConfig c;
  c.hidden_dim = hidden_dim;
  c.num_layers = num_layers;
  c.actor_lr = actor_lr;
  c.critic_lr = critic_lr;
  c.alpha_lr = alpha_lr;
  c.discount = discount;
  c.tau = tau;
  c.init_temperature = init_temperature;
  c.batch_size = batch_size;
  c.target_entropy = target_entropy;
  c.log_std_min = log_std_min;
  c.log_std_max = log_std_max;
  c.actor_update_freq = actor_update_freq;
  c.critic_target_update_freq = critic_target_update_freq;
  c.max_critic_loss = max_critic_loss;
  c.seed = MixSeed(seed, static_cast<uint64_t>(task) + 1);
  return c;
}

DistralLearner::DistralLearner(const DistralConfig& config, int64_t obs_dim, int64_t action_dim,
                               int64_t num_tasks)
    : config_(Validated(config)),
      obs_dim_(obs_dim),
      action_dim_(action_dim),
      num_tasks_(num_tasks),
      generator_(at::detail::createCPUGenerator(config.seed)),
      distilled_optimizer_(0, nn::AdamOptions{}) {
  if (obs_dim <= 0 || action_dim <= 0 || num_tasks <= 0) {
    throw ConfigError("DistralLearner: obs_dim, action_dim and num_tasks must be > 0");
  }
  nn::GaussianPolicyOptions policy;
  policy.obs_dim = obs_dim;
  policy.action_dim = action_dim;
  policy.hidden_dim = config.hidden_dim;
  policy.num_layers = config.num_layers;
  policy.log_std_min = config.log_std_min;
  policy.log_std_max = config.log_std_max;
  distilled_ = nn::GaussianPolicy(policy, generator_);
  {
    // pi_0 starts as N(0, 1) in pre-tanh space for every observation (output
    // weights 0, mean bias 0, log-std bias where the bound maps it to 0): the
    // prior terms c log pi_0(a) of the first updates are then of order c a^2.
    // Drawn like the actor, its log-std would start anywhere in [-20, 2], and
    // log pi_0 of the task agents' actions near -1e8 (a diverged critic at the
    // first update, found by tests/agents/distral_test.cc).
    torch::NoGradGuard no_grad;
    const std::vector<torch::Tensor>& p = distilled_->trunk()->detached_params();
    p[p.size() - 2].zero_();
    const double lo = config.log_std_min, hi = config.log_std_max;
    const double raw = std::atanh(std::clamp((0.0 - lo) / (0.5 * (hi - lo)) - 1.0, -0.999, 0.999));
    p.back().narrow(0, 0, action_dim).zero_();
    p.back().narrow(0, action_dim, action_dim).fill_(raw);
  }
  nn::AdamOptions adam;
  adam.lr = config.distilled_lr;
  distilled_optimizer_ = nn::FlatAdam(distilled_->trunk()->num_params(), adam);
  PolicyPrior prior;
  prior.weight = config.distral_alpha;
  prior.log_prob = [this](const torch::Tensor& obs, const torch::Tensor& u) {
    return DistilledLogProb(obs, u);
  };
  for (int64_t t = 0; t < num_tasks; ++t) {
    task_agents_.push_back(
        std::make_unique<SacLearner>(config.TaskAgentConfig(t), obs_dim, action_dim, 1));
    if (config.distral_alpha > 0.0) task_agents_.back()->SetPrior(prior);
  }
}

torch::Tensor DistralLearner::DistilledLogProb(const torch::Tensor& obs,
                                               const torch::Tensor& u) const {
  const nn::PolicyOutput out =
      distilled_->Forward(obs, {}, distilled_->trunk()->detached_params());
  return nn::DiagGaussianLogProb(u, out.mean, out.log_std) - nn::TanhLogAbsDetJacobian(u);
}

Metrics DistralLearner::Update(const Batch& batch) {
  ValidateBatch(batch, obs_dim_, action_dim_, num_tasks_);
  Metrics metrics;
  std::map<std::string, double> sums;
  int present = 0;
  std::vector<torch::Tensor> means, log_stds, row_lists;
  for (int64_t t = 0; t < num_tasks_; ++t) {
    const torch::Tensor rows = torch::nonzero(batch.task_index == t).reshape({-1});
    if (rows.numel() == 0) continue;
    const Batch part = TaskRows(batch, rows);
    const Metrics m = task_agents_[static_cast<size_t>(t)]->Update(part);
    for (const auto& [name, value] : m.items()) sums[name] += value;
    ++present;
    // The task policy after its step, fixed for the distillation.
    torch::NoGradGuard no_grad;
    SacLearner& agent = *task_agents_[static_cast<size_t>(t)];
    const nn::PolicyOutput out =
        agent.actor()->Forward(part.obs, {}, agent.actor()->trunk()->detached_params());
    means.push_back(out.mean);
    log_stds.push_back(out.log_std);
    row_lists.push_back(rows);
  }
  for (const auto& [name, value] : sums) metrics.Set(name, value / present);

  // Distillation: distral_alpha * mean_rows KL(pi_i || pi_0).
  const torch::Tensor rows = torch::cat(row_lists);
  const nn::PolicyOutput pi0 = distilled_->forward(batch.obs.index_select(0, rows));
  const torch::Tensor kl =
      DiagGaussianKl(torch::cat(means), torch::cat(log_stds), pi0.mean, pi0.log_std);
  metrics.Set("distill_kl", kl.mean().item<double>());
  if (config_.distral_alpha > 0.0) {
    distilled_->trunk()->ZeroGrad();
    (config_.distral_alpha * kl.mean()).backward();
    distilled_optimizer_.Step(distilled_->trunk()->flat(), distilled_->trunk()->flat_grad());
  }
  ++num_updates_;
  return metrics;
}

torch::Tensor DistralLearner::Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                                  bool deterministic) {
  c10::InferenceMode inference;
  if (obs.dim() != 2 || obs.size(1) != obs_dim_ || !task_index.defined() ||
      task_index.dim() != 1 || task_index.size(0) != obs.size(0) ||
      task_index.scalar_type() != torch::kInt64) {
    throw Error("DistralLearner::Act: obs must be (B, " + std::to_string(obs_dim_) +
                ") with an int64 task_index of shape (B)");
  }
  if (obs.size(0) > 0) {
    auto [lo, hi] = torch::aminmax(task_index);
    if (lo.item<int64_t>() < 0 || hi.item<int64_t>() >= num_tasks_) {
      throw Error("DistralLearner::Act: task indices must lie in [0, " +
                  std::to_string(num_tasks_) + ")");
    }
  }
  const torch::Tensor x = obs.to(torch::kFloat32);
  if (config_.act_with == "distilled") {
    const nn::PolicyOutput out = distilled_->forward(x);
    return deterministic ? torch::tanh(out.mean)
                         : nn::SampleSquashedGaussian(out.mean, out.log_std, generator_).action;
  }
  torch::Tensor actions = torch::empty({obs.size(0), action_dim_}, torch::kFloat32);
  for (int64_t t = 0; t < num_tasks_; ++t) {
    const torch::Tensor rows = torch::nonzero(task_index == t).reshape({-1});
    if (rows.numel() == 0) continue;
    actions.index_copy_(0, rows,
                        task_agents_[static_cast<size_t>(t)]->Act(x.index_select(0, rows),
                                                                  deterministic));
  }
  return actions;
}

ActOutput DistralLearner::Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                              ActorState&, ActMode mode) {
  ActOutput out;
  out.action = Act(obs, task_index, mode == ActMode::kDeterministic);
  return out;
}

void DistralLearner::Save(torch::serialize::OutputArchive& archive) const {
  archive.write("distral_tasks", torch::tensor(num_tasks_, torch::kInt64));
  for (int64_t t = 0; t < num_tasks_; ++t) {
    torch::serialize::OutputArchive agent;
    task_agents_[static_cast<size_t>(t)]->Save(agent);
    archive.write("task_agent_" + std::to_string(t), agent);
  }
  Transfer(archive, "distilled", *distilled_->trunk());
  Transfer(archive, "distilled_optimizer", distilled_optimizer_);
  WriteProgress(archive, num_updates_, generator_);
}

void DistralLearner::Load(torch::serialize::InputArchive& archive) {
  torch::Tensor tasks;
  if (!archive.try_read("distral_tasks", tasks)) {
    throw Error("DistralLearner::Load: not a Distral checkpoint");
  }
  if (tasks.item<int64_t>() != num_tasks_) {
    throw Error("DistralLearner::Load: the checkpoint has " +
                std::to_string(tasks.item<int64_t>()) + " task agents, this learner " +
                std::to_string(num_tasks_));
  }
  for (int64_t t = 0; t < num_tasks_; ++t) {
    torch::serialize::InputArchive agent;
    archive.read("task_agent_" + std::to_string(t), agent);
    task_agents_[static_cast<size_t>(t)]->Load(agent);
  }
  Transfer(archive, "distilled", *distilled_->trunk());
  Transfer(archive, "distilled_optimizer", distilled_optimizer_);
  ReadProgress(archive, num_updates_, generator_);
}

}  // namespace manyworlds::agents
