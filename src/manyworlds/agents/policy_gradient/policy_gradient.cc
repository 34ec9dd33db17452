#include "manyworlds/agents/policy_gradient/policy_gradient.h"

#include <cmath>
#include <string>
#include <vector>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/pcgrad.h"
#include "manyworlds/nn/threads.h"
#include "manyworlds/rl/generator.h"

namespace manyworlds::agents {
namespace {

// An algorithm's registry name as int64 character codes (checkpoint tag).
torch::Tensor NameTensor(const std::string& name) {
  std::vector<int64_t> codes(name.begin(), name.end());
  return torch::tensor(codes, torch::kInt64);
}

}  // namespace
double ExplainedVariance(const torch::Tensor& prediction, const torch::Tensor& target) {
  const double var = target.var(/*unbiased=*/false).item<double>();
  if (!(var > 0)) return 0.0;
  return 1.0 - (target - prediction).var(/*unbiased=*/false).item<double>() / var;
}

void RequireFinite(const torch::Tensor& t, const char* algo, const char* what) {
  if (!torch::isfinite(t).all().item<bool>()) {
    throw Error(std::string(algo) + " update: " + what +
                " are not finite (the training diverged; try a smaller learning rate or "
                "another baseline)");
  }
}

double ClipGradNorm(const torch::Tensor& grad, double max_norm) {
  const double norm = grad.norm().item<double>();
  if (max_norm > 0 && norm > max_norm) grad.mul_(max_norm / (norm + 1e-6));
  return norm;
}

double ClipGradNorm(const std::vector<nn::FlatModule*>& modules, double max_norm) {
  if (modules.size() == 1) return ClipGradNorm(modules[0]->flat_grad(), max_norm);
  double squares = 0.0;
  for (const nn::FlatModule* m : modules) squares += m->flat_grad().square().sum().item<double>();
  const double norm = std::sqrt(squares);
  if (max_norm > 0 && norm > max_norm) {
    for (const nn::FlatModule* m : modules) m->flat_grad().mul_(max_norm / (norm + 1e-6));
  }
  return norm;
}

PolicyGradientLearner::PolicyGradientLearner(const PolicyGradientConfig& config,
                                             const PolicySpaces& spaces)
    : config_(Validated(config)),
      spaces_(spaces),
      generator_(rl::MakeGenerator(config.seed)),
      value_optimizer_(0, nn::AdamOptions{.lr = config.vf_lr}) {
  if (spaces.obs_dim <= 0 || spaces.action_dim <= 0 || spaces.num_tasks <= 0) {
    throw ConfigError("policy-gradient learner: obs_dim, action_dim and num_tasks must be > 0");
  }
  nn::ConfigureTorchThreads();
  // Draw order from the generator: conditioning, policy, value network.
  nn::TaskConditioningOptions c;
  c.architecture = config.architecture;
  c.obs_dim = spaces.obs_dim;
  c.num_tasks = spaces.num_tasks;
  c.task_embedding_dim = config.task_embedding_dim;
  c.num_experts = config.num_experts;
  c.encoder_dim = config.encoder_dim;
  conditioning_ = std::make_unique<nn::TaskConditioning>(c, generator_);
  input_dim_ = conditioning_->output_dim();
  const int64_t heads = conditioning_->multihead() ? spaces.num_tasks : 1;
  nn::StochasticPolicyOptions p = PolicyNetworkOptions(config, spaces, input_dim_);
  p.num_heads = heads;
  policy_ = nn::StochasticPolicy(p, generator_);
  policy_modules_.push_back(policy_.get());
  for (nn::FlatModule* m : conditioning_->modules()) policy_modules_.push_back(m);
  if (config.baseline == "mlp") {
    value_ = nn::ValueNetwork(input_dim_, config.vf_hidden_dim, config.vf_num_layers, heads,
                              generator_);
    value_optimizer_ = nn::FlatAdam(value_->num_params(), nn::AdamOptions{.lr = config.vf_lr});
  } else {
    linear_ = std::make_unique<rl::LinearFeatureBaseline>(input_dim_);
  }
}

torch::Tensor PolicyGradientLearner::Heads(const torch::Tensor& task_index) const {
  return config_.architecture == "multihead" ? task_index : torch::Tensor();
}

torch::Tensor PolicyGradientLearner::NetworkInput(const torch::Tensor& obs,
                                                  const torch::Tensor& task_index) const {
  torch::NoGradGuard no_grad;
  return conditioning_->Forward(obs, task_index);
}

nn::ActionDistribution PolicyGradientLearner::PolicyOn(const PolicySamples& s,
                                                       const torch::Tensor& rows) const {
  const bool all = !rows.defined();
  const torch::Tensor head =
      !s.head.defined() || all ? s.head : s.head.index_select(0, rows);
  if (conditioning_->modules().empty()) {
    return policy_->Forward(all ? s.x : s.x.index_select(0, rows), head);
  }
  const torch::Tensor x = all ? conditioning_->Forward(s.obs, s.tasks)
                              : conditioning_->Forward(s.obs.index_select(0, rows),
                                                       s.tasks.index_select(0, rows));
  return policy_->Forward(x, head);
}

ActOutput PolicyGradientLearner::Act(const torch::Tensor& obs, const torch::Tensor& task_index,
                                     ActorState& state, ActMode mode) {
  c10::InferenceMode inference;
  if (obs.dim() != 2 || obs.size(1) != spaces_.obs_dim || task_index.dim() != 1 ||
      task_index.size(0) != obs.size(0)) {
    throw Error(std::string(algo_name()) + " actor: expected obs (N, " +
                std::to_string(spaces_.obs_dim) + ") and task_index (N)");
  }
  const nn::ActionDistribution d =
      policy_->Forward(NetworkInput(obs, task_index), Heads(task_index));
  ActOutput out;
  out.action =
      mode == ActMode::kSample ? d.Sample(SamplingGenerator(state, generator_)) : d.Mode();
  out.log_prob = d.LogProb(out.action);
  return out;
}

torch::Tensor PolicyGradientLearner::Values(const torch::Tensor& x, const torch::Tensor& head,
                                            const torch::Tensor& t) const {
  torch::NoGradGuard no_grad;
  if (value_) return value_->Forward(x, head);
  return linear_->Predict(x, t);
}

Metrics PolicyGradientLearner::Update(rl::RolloutBuffer& rollout) {
  const int64_t b = rollout.size();
  const torch::Tensor tasks = rollout.FlatTasks();
  const torch::Tensor head = Heads(tasks);
  const torch::Tensor x = NetworkInput(rollout.FlatObs(), tasks);
  const torch::Tensor t = rollout.episode_steps.reshape({b});
  {
    torch::NoGradGuard no_grad;
    rollout.values.copy_(Values(x, head, t).reshape(rollout.values.sizes()));
    const torch::Tensor final_x =
        NetworkInput(rollout.final_obs.reshape({b, spaces_.obs_dim}), tasks);
    const torch::Tensor boot = Values(final_x, head, t + 1).reshape(rollout.values.sizes());
    rollout.bootstrap_values.copy_(boot * rollout.ended * (1.0 - rollout.terminated));
  }
  Metrics metrics;
  torch::Tensor raw_rewards;
  if (config_.entropy_method == "max" && config_.entropy_coeff > 0) {
    raw_rewards = rollout.rewards.clone();
    rollout.rewards.add_(-config_.entropy_coeff * rollout.log_probs);
  }
  RequireFinite(rollout.values, algo_name(), "the baseline's values");
  RequireFinite(rollout.bootstrap_values, algo_name(), "the baseline's values");
  rollout.ComputeAdvantages(config_.discount, config_.gae_lambda);
  if (linear_) linear_->Fit(x, t, rollout.DiscountedReturns(config_.discount).reshape({b}));
  if (raw_rewards.defined()) rollout.rewards.copy_(raw_rewards);

  PolicySamples s;
  s.x = x;
  s.obs = rollout.FlatObs();
  s.tasks = tasks;
  s.head = head;
  s.actions = rollout.FlatActions();
  s.log_probs = rollout.log_probs.reshape({b});
  s.returns = rollout.returns.reshape({b});
  s.episode_steps = t;
  torch::Tensor adv = rollout.advantages.reshape({b});
  if (config_.center_advantages && b > 1) adv = (adv - adv.mean()) / (adv.std() + 1e-8);
  s.advantages = adv;
  metrics.Set("explained_variance", ExplainedVariance(rollout.values.reshape({b}), s.returns));
  const Metrics optimized = OptimizePolicy(s);
  RequireFinite(policy_->flat(), algo_name(), "the policy's parameters");
  for (const auto& [name, value] : optimized.items()) metrics.Set(name, value);
  ++num_updates_;
  return metrics;
}

double PolicyGradientLearner::ValueStep(const PolicySamples& s, const torch::Tensor& rows) {
  const torch::Tensor head = s.head.defined() ? s.head.index_select(0, rows) : torch::Tensor();
  const torch::Tensor v = value_->Forward(s.x.index_select(0, rows), head);
  const torch::Tensor per_sample = (v - s.returns.index_select(0, rows)).square();
  const torch::Tensor loss = per_sample.mean();
  value_->ZeroGrad();
  if (config_.pcgrad) {
    nn::PcGradBackward(per_sample, s.tasks.index_select(0, rows), spaces_.num_tasks,
                       {value_.get()}, generator_);
  } else {
    loss.backward();
  }
  value_optimizer_.Step(value_->flat(), value_->flat_grad());
  return loss.item<double>();
}

double PolicyGradientLearner::FitValue(const PolicySamples& s, int64_t epochs,
                                       int64_t minibatch_size) {
  if (!value_) return 0.0;
  const int64_t b = s.size();
  double sum = 0.0;
  int64_t count = 0;
  for (int64_t e = 0; e < epochs; ++e) {
    const torch::Tensor perm = torch::randperm(b, generator_, torch::kInt64);
    for (int64_t lo = 0; lo < b; lo += minibatch_size) {
      sum += ValueStep(s, perm.narrow(0, lo, std::min(minibatch_size, b - lo)));
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

template <typename Archive, typename Self>
void PolicyGradientLearner::TransferNetworks(Archive& archive, Self& self) {
  Transfer(archive, "policy", *self.policy_);
  for (size_t i = 1; i < self.policy_modules_.size(); ++i) {
    Transfer(archive, ("conditioning_" + std::to_string(i)).c_str(), *self.policy_modules_[i]);
  }
  TransferBaseline(archive, self.value_, self.value_optimizer_, self.linear_);
}

void PolicyGradientLearner::Save(torch::serialize::OutputArchive& archive) const {
  // "algo" (the name's first letter) is what checkpoints before the whole
  // name carried; trpo and te_ppo share it, hence "algo_name".
  archive.write("algo", torch::tensor(static_cast<int64_t>(algo_name()[0]), torch::kInt64));
  archive.write("algo_name", NameTensor(algo_name()));
  archive.write("input_dim", torch::tensor(input_dim_, torch::kInt64));
  TransferNetworks(archive, *this);
  SaveExtra(archive);
  WriteProgress(archive, num_updates_, generator_);
}

void PolicyGradientLearner::Load(torch::serialize::InputArchive& archive) {
  torch::Tensor algo, input_dim;
  torch::Tensor name;
  const bool same_name = archive.try_read("algo_name", name)
                             ? torch::equal(name, NameTensor(algo_name()))
                             : archive.try_read("algo", algo) && algo.numel() == 1 &&
                                   algo.item<int64_t>() == static_cast<int64_t>(algo_name()[0]);
  if (!same_name || !archive.try_read("input_dim", input_dim) || input_dim.numel() != 1 ||
      input_dim.item<int64_t>() != input_dim_) {
    throw Error(std::string(algo_name()) +
                " checkpoint: not a checkpoint of this algorithm and network input");
  }
  TransferNetworks(archive, *this);
  LoadExtra(archive);
  ReadProgress(archive, num_updates_, generator_);
}

}  // namespace manyworlds::agents
