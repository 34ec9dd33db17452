#include "manyworlds/agents/maml/maml.h"

#include <cmath>
#include <functional>
#include <string>

#include "manyworlds/agents/archive_io.h"
#include "manyworlds/agents/config_check.h"
#include "manyworlds/agents/ppo/ppo.h"
#include "manyworlds/agents/trpo/trpo.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/threads.h"
#include "manyworlds/rl/generator.h"
#include "manyworlds/rl/linear_baseline.h"
#include "manyworlds/rl/rollout_buffer.h"

namespace manyworlds::agents {
namespace {

// Names of this actor's ActorState entries.
constexpr char kMamlHistory[] = "history";
constexpr char kAdapted[] = "adapted";

constexpr int64_t kMamlCheckpointCode = 0x6d616d6c;  // "maml"
constexpr uint64_t kValueSeedSalt = 0x76616c7565;  // "value"

std::vector<torch::Tensor> Grad(const torch::Tensor& y, at::ArrayRef<torch::Tensor> params,
                                bool create_graph) {
  return torch::autograd::grad({y}, params.vec(), {}, /*retain_graph=*/true, create_graph,
                               /*allow_unused=*/true);
}

// One env's data of a rollout (rows [begin, end) of column i).
struct Column {
  torch::Tensor obs, actions, log_probs, rewards, ended;
};

Column Slice(const rl::RolloutBuffer& r, int64_t begin, int64_t end, int64_t i) {
  Column c;
  const int64_t n = end - begin;
  c.obs = r.obs.narrow(0, begin, n).select(1, i);
  c.actions = r.actions.narrow(0, begin, n).select(1, i);
  c.log_probs = r.log_probs.narrow(0, begin, n).select(1, i);
  c.rewards = r.rewards.narrow(0, begin, n).select(1, i);
  c.ended = r.ended.narrow(0, begin, n).select(1, i).clone();
  c.ended[n - 1].fill_(1.0f);
  return c;
}

}  // namespace

void MamlConfig::Validate() const {
  RequireField(hidden_dim > 0 && hidden_dim <= 65536, "hidden_dim", "in [1, 65536]", hidden_dim);
  RequireField(num_layers >= 0 && num_layers <= 64, "num_layers", "in [0, 64]", num_layers);
  RequireStdBounds("", min_std, max_std, init_std);
  RequireField(FinitePositive(inner_lr), "inner_lr", "finite and > 0", inner_lr);
  RequireField(episodes_per_task >= 1 && episodes_per_task <= 10000, "episodes_per_task",
               "in [1, 10000]", episodes_per_task);
  RequireDiscountAndLambda(discount, gae_lambda);
  RequireField(outer == "trpo" || outer == "ppo", "outer", "one of trpo, ppo", outer);
  RequireField(baseline == "linear" || baseline == "value_network", "baseline",
               "one of linear, value_network", baseline);
  RequireField(value_hidden_dim > 0 && value_hidden_dim <= 65536, "value_hidden_dim",
               "in [1, 65536]", value_hidden_dim);
  RequireField(value_num_layers >= 0 && value_num_layers <= 64, "value_num_layers", "in [0, 64]",
               value_num_layers);
  RequireField(FinitePositive(value_lr), "value_lr", "finite and > 0", value_lr);
  RequireField(value_fit_steps >= 1 && value_fit_steps <= 100000, "value_fit_steps",
               "in [1, 100000]", value_fit_steps);
  RequireField(FinitePositive(outer_lr), "outer_lr", "finite and > 0", outer_lr);
  RequireField(outer_epochs >= 1 && outer_epochs <= 10000, "outer_epochs", "in [1, 10000]",
               outer_epochs);
  RequireField(clip_range > 0 && clip_range < 1, "clip_range", "in (0, 1)", clip_range);
  RequireField(FinitePositive(max_kl), "max_kl", "finite and > 0", max_kl);
  RequireField(cg_iters >= 1 && cg_iters <= 1000, "cg_iters", "in [1, 1000]", cg_iters);
  RequireField(std::isfinite(cg_damping) && cg_damping >= 0, "cg_damping", "finite and >= 0",
               cg_damping);
  RequireField(backtrack_ratio > 0 && backtrack_ratio < 1, "backtrack_ratio", "in (0, 1)",
               backtrack_ratio);
  RequireField(max_backtracks >= 1 && max_backtracks <= 1000, "max_backtracks", "in [1, 1000]",
               max_backtracks);
}

MamlLearner::MamlLearner(const MamlConfig& config, const PolicySpaces& spaces)
    : config_(Validated(config)),
      spaces_(spaces),
      generator_(rl::MakeGenerator(config.seed)),
      outer_optimizer_(0, nn::AdamOptions{.lr = config.outer_lr}) {
  if (spaces.obs_dim <= 0 || spaces.action_dim <= 0) {
    throw ConfigError("maml: obs_dim and action_dim must be > 0");
  }
  nn::ConfigureTorchThreads();
  // the task is never an input: it is adapted to
  policy_ = nn::StochasticPolicy(PolicyNetworkOptions(config, spaces, spaces.obs_dim), generator_);
  outer_optimizer_ = nn::FlatAdam(policy_->num_params(), nn::AdamOptions{.lr = config.outer_lr});
  if (config.baseline == "value_network") {
    // its own generator, so the policy's draws are those of a linear-baseline run
    at::Generator value_generator = rl::MakeGenerator(config.seed ^ kValueSeedSalt);
    nn::MlpOptions v;
    v.input_dim = spaces.obs_dim + 1;
    v.output_dim = 1;
    v.hidden_dim = config.value_hidden_dim;
    v.num_layers = config.value_num_layers;
    v.activation = nn::Activation::kTanh;
    value_net_ = nn::Mlp(v, value_generator);
    value_init_ = value_net_->flat().detach().clone();
  }
}

torch::Tensor MamlLearner::BaselineValues(const torch::Tensor& obs, const torch::Tensor& steps,
                                          const torch::Tensor& returns,
                                          const torch::Tensor& fit_rows) {
  if (config_.baseline == "linear") {
    torch::NoGradGuard no_grad;
    rl::LinearFeatureBaseline baseline(spaces_.obs_dim);
    baseline.Fit(obs.index_select(0, fit_rows), steps.index_select(0, fit_rows),
                 returns.index_select(0, fit_rows));
    return baseline.Predict(obs, steps);
  }
  c10::InferenceMode off(false);
  torch::AutoGradMode grad(true);
  const torch::Tensor x = torch::cat({obs, (steps / 100.0f).unsqueeze(1)}, 1).detach();
  const torch::Tensor target = returns.index_select(0, fit_rows).detach();
  const torch::Tensor fit_x = x.index_select(0, fit_rows);
  // standardised targets: one learning rate serves every reward scale
  const double mean = target.mean().item<double>();
  const double scale =
      target.numel() > 1 ? std::max(target.std().item<double>(), 1e-6) : 1.0;
  const torch::Tensor y = ((target - mean) / scale).unsqueeze(1);
  {
    torch::NoGradGuard no_grad;
    value_net_->flat().copy_(value_init_);
  }
  nn::FlatAdam adam(value_net_->num_params(), nn::AdamOptions{.lr = config_.value_lr});
  for (int64_t k = 0; k < config_.value_fit_steps; ++k) {
    const torch::Tensor loss = (value_net_->Forward(fit_x) - y).pow(2).mean();
    value_net_->ZeroGrad();
    loss.backward();
    adam.Step(value_net_->flat(), value_net_->flat_grad());
  }
  torch::NoGradGuard no_grad;
  return value_net_->Forward(x).squeeze(1) * scale + mean;
}

torch::Tensor MamlLearner::Advantages(const torch::Tensor& obs, const torch::Tensor& rewards,
                                      const torch::Tensor& ended,
                                      const torch::Tensor& valid) {
  torch::NoGradGuard no_grad;
  const int64_t t_len = rewards.size(0);
  // step within the episode, and discounted returns (every end terminal)
  torch::Tensor steps = torch::empty({t_len});
  torch::Tensor returns = torch::empty({t_len});
  const float* end = ended.contiguous().data_ptr<float>();
  const torch::Tensor r_c = rewards.contiguous();
  const float* r = r_c.data_ptr<float>();
  float* s = steps.data_ptr<float>();
  float* g = returns.data_ptr<float>();
  float t = 0.0f;
  for (int64_t k = 0; k < t_len; ++k) {
    s[k] = t;
    t = end[k] > 0.5f ? 0.0f : t + 1.0f;
  }
  double next = 0.0;
  for (int64_t k = t_len - 1; k >= 0; --k) {
    if (end[k] > 0.5f) next = 0.0;
    next = r[k] + config_.discount * next;
    g[k] = static_cast<float>(next);
  }
  const torch::Tensor rows = valid.nonzero().squeeze(1);
  const torch::Tensor values = BaselineValues(obs, steps, returns, rows).detach();
  const torch::Tensor flags = ended.reshape({t_len, 1});
  torch::Tensor adv =
      rl::ComputeGae(rewards.reshape({t_len, 1}), values.reshape({t_len, 1}), flags, flags,
                     torch::zeros({t_len, 1}), config_.discount, config_.gae_lambda)
          .reshape({t_len});
  if (config_.center_advantages && rows.size(0) > 1) {
    const torch::Tensor a = adv.index_select(0, rows);
    adv = (adv - a.mean()) / (a.std() + 1e-8);
  }
  return adv * valid;
}

std::vector<torch::Tensor> MamlLearner::InnerStep(at::ArrayRef<torch::Tensor> params,
                                                  const MamlEpisodes& e,
                                                  const torch::Tensor& weights,
                                                  bool create_graph) const {
  const nn::ActionDistribution d = policy_->Forward(e.obs, {}, params);
  const torch::Tensor loss =
      -(d.LogProb(e.actions) * e.advantages * weights).sum() / weights.sum().clamp_min(1.0);
  const std::vector<torch::Tensor> grads = Grad(loss, params, create_graph);
  std::vector<torch::Tensor> adapted;
  for (size_t j = 0; j < params.size(); ++j) {
    adapted.push_back(grads[j].defined() ? params[j] - config_.inner_lr * grads[j] : params[j]);
  }
  return adapted;
}

ActOutput MamlLearner::Act(const torch::Tensor& obs, const torch::Tensor&, ActorState& state,
                           ActMode mode) {
  c10::InferenceMode inference;
  if (obs.dim() != 2 || obs.size(1) != spaces_.obs_dim) {
    throw Error("maml actor: expected obs (N, " + std::to_string(spaces_.obs_dim) + ")");
  }
  at::Generator& gen = SamplingGenerator(state, generator_);
  auto act = [&](const nn::ActionDistribution& d) {
    ActOutput out;
    out.action = mode == ActMode::kSample ? d.Sample(gen) : d.Mode();
    out.log_prob = d.LogProb(out.action);
    return out;
  };
  if (state.lists[kAdapted].empty()) return act(policy_->Forward(obs));
  // each env with its own adapted parameters
  std::vector<torch::Tensor> actions, log_probs;
  std::vector<torch::Tensor> params(state.lists[kAdapted].size());
  for (int64_t i = 0; i < obs.size(0); ++i) {
    for (size_t j = 0; j < params.size(); ++j) params[j] = state.lists[kAdapted][j][i];
    const ActOutput out = act(policy_->Forward(obs.narrow(0, i, 1), {}, params));
    actions.push_back(out.action);
    log_probs.push_back(out.log_prob);
  }
  ActOutput out;
  out.action = torch::cat(actions);
  out.log_prob = torch::cat(log_probs);
  return out;
}

void MamlLearner::Reset(const torch::Tensor& envs, ResetScope scope, ActorState& state) {
  if (scope == ResetScope::kEpisode) return;
  const torch::Tensor mask = envs.to(torch::kBool);
  if (mask.all().item<bool>()) {
    state.lists[kMamlHistory].clear();
    state.lists[kAdapted].clear();
    return;
  }
  // forget the masked rows only: their records stop counting, their policy is theta again
  ForgetHistoryRows(state.lists[kMamlHistory], mask);
  for (size_t j = 0; j < state.lists[kAdapted].size(); ++j) {
    std::vector<int64_t> shape(state.lists[kAdapted][j].dim(), 1);
    shape[0] = mask.size(0);
    state.lists[kAdapted][j] = torch::where(
        mask.reshape(shape), policy_->params()[j].detach().unsqueeze(0), state.lists[kAdapted][j]);
  }
}

void MamlLearner::Observe(const StepOutcome& o, ActorState& state) {
  c10::InferenceMode inference;
  const int64_t n = o.obs.size(0);
  const torch::Tensor valid = o.valid.defined() ? o.valid : torch::ones({n});
  state.lists[kMamlHistory].push_back(
      torch::cat({o.obs, o.action.to(torch::kFloat32), o.reward.reshape({n, 1}),
                  o.ended.reshape({n, 1}), valid.reshape({n, 1})},
                 1)
          .clone());
}

void MamlLearner::Adapt(const torch::Tensor& envs, ActorState& state) {
  if (state.lists[kMamlHistory].empty()) return;
  c10::InferenceMode off(false);
  torch::AutoGradMode grad(true);
  // (T, N, D) rows [obs, action, reward, ended, valid]; inference tensors
  // become normal ones by the clone
  const torch::Tensor h = torch::stack(state.lists[kMamlHistory]).clone();
  const int64_t d_obs = spaces_.obs_dim, d_act = spaces_.action_dim;
  const int64_t n = h.size(1);
  const std::vector<torch::Tensor>& theta = policy_->params();
  std::vector<std::vector<torch::Tensor>> rows(theta.size());
  const torch::Tensor mask = envs.to(torch::kBool);
  // the training loop adapts every env once per iteration; its update reuses this inner step
  const bool keep = state.learning && mask.all().item<bool>() &&
                    h.select(2, h.size(2) - 1).all().item<bool>();
  adaptation_ = {};
  if (keep) adaptation_.num_updates = num_updates_;
  for (int64_t i = 0; i < n; ++i) {
    std::vector<torch::Tensor> adapted;
    if (mask[i].item<bool>()) {
      const torch::Tensor col = h.select(1, i);
      MamlEpisodes e;
      e.obs = col.narrow(1, 0, d_obs);
      e.actions = col.narrow(1, d_obs, d_act);
      e.returns = col.select(1, d_obs + d_act);
      torch::Tensor ended = col.select(1, d_obs + d_act + 1).clone();
      const torch::Tensor valid = col.select(1, d_obs + d_act + 2);
      ended[ended.size(0) - 1].fill_(1.0f);
      e.advantages = Advantages(e.obs, e.returns, ended, valid);
      std::vector<torch::Tensor> step = InnerStep(theta, e, valid, /*create_graph=*/keep);
      for (const torch::Tensor& p : step) adapted.push_back(p.detach());
      if (keep) {
        adaptation_.pre.push_back(e);
        adaptation_.ended.push_back(ended);
        adaptation_.adapted.push_back(std::move(step));
      }
    } else if (!state.lists[kAdapted].empty()) {
      for (const torch::Tensor& p : state.lists[kAdapted]) adapted.push_back(p[i]);
    } else {
      for (const torch::Tensor& p : theta) adapted.push_back(p.detach());
    }
    for (size_t j = 0; j < theta.size(); ++j) rows[j].push_back(adapted[j]);
  }
  state.lists[kAdapted].clear();
  for (auto& r : rows) state.lists[kAdapted].push_back(torch::stack(r));
  state.lists[kMamlHistory].clear();
}

bool MamlLearner::Adapted(int64_t i, const MamlEpisodes& pre, const torch::Tensor& ended) const {
  const Adaptation& a = adaptation_;
  if (a.num_updates != num_updates_ || i >= static_cast<int64_t>(a.pre.size())) return false;
  const MamlEpisodes& e = a.pre[i];
  return torch::equal(e.obs, pre.obs) && torch::equal(e.actions, pre.actions) &&
         torch::equal(e.returns, pre.returns) && torch::equal(a.ended[i], ended);
}

Metrics MamlLearner::Update(rl::RolloutBuffer& rollout) {
  const int64_t steps = rollout.steps();
  const int64_t n = rollout.envs();
  const int64_t k2 = 2 * config_.episodes_per_task;
  if (steps % k2 != 0) {
    throw Error("maml update: the rollout must hold 2 x episodes_per_task rounds");
  }
  const int64_t pre_len = steps / 2;
  std::vector<MamlEpisodes> pre(n), post(n);
  // each env's adapted parameters at theta with the inner step's graph
  std::vector<std::vector<torch::Tensor>> adapted(n);
  const bool whole_adaptation = static_cast<int64_t>(adaptation_.pre.size()) == n;
  double pre_return = 0.0, post_return = 0.0, pre_episodes = 0.0, post_episodes = 0.0;
  const torch::Tensor ones_pre = torch::ones({pre_len});
  int64_t reused = 0;
  for (int64_t i = 0; i < n; ++i) {
    const Column a = Slice(rollout, 0, pre_len, i);
    const Column b = Slice(rollout, pre_len, steps, i);
    pre[i] = {a.obs, a.actions, a.log_probs, torch::Tensor(), a.rewards};
    if (whole_adaptation && Adapted(i, pre[i], a.ended)) {
      pre[i].advantages = adaptation_.pre[i].advantages;
      adapted[i] = std::move(adaptation_.adapted[i]);
      ++reused;
    } else {
      pre[i].advantages = Advantages(a.obs, a.rewards, a.ended, ones_pre);
      adapted[i] = InnerStep(policy_->params(), pre[i], ones_pre, /*create_graph=*/true);
    }
    post[i] = {b.obs, b.actions, b.log_probs, Advantages(b.obs, b.rewards, b.ended, ones_pre),
               b.rewards};
    pre_return += a.rewards.sum().item<double>();
    post_return += b.rewards.sum().item<double>();
    pre_episodes += a.ended.sum().item<double>();
    post_episodes += b.ended.sum().item<double>();
  }
  adaptation_ = {};
  const std::vector<torch::Tensor>& params = policy_->params();

  // TRPO: the post-adaptation policies at the current theta (the KL's reference)
  std::vector<nn::ActionDistribution> old;
  // the surrogate (and KL) of the post-adaptation policies whose parameters
  // env i's `inner(i)` gives
  auto objective = [&](const std::function<std::vector<torch::Tensor>(int64_t)>& inner,
                       torch::Tensor* kl) {
    torch::Tensor surrogate = torch::zeros({});
    torch::Tensor divergence = torch::zeros({});
    for (int64_t i = 0; i < n; ++i) {
      const nn::ActionDistribution d = policy_->Forward(post[i].obs, {}, inner(i));
      surrogate =
          surrogate +
          ((d.LogProb(post[i].actions) - post[i].log_probs).exp() * post[i].advantages).mean();
      if (kl != nullptr) divergence = divergence + old[i].KlTo(d).mean();
    }
    if (kl != nullptr) *kl = divergence / static_cast<double>(n);
    return surrogate / static_cast<double>(n);
  };
  auto at_theta = [&](int64_t i) { return adapted[i]; };

  Metrics m;
  m.Set("pre_adaptation_return", pre_return / std::max(1.0, pre_episodes));
  m.Set("post_adaptation_return", post_return / std::max(1.0, post_episodes));
  // the share of envs whose inner step at theta was Adapt's (1 in training)
  m.Set("inner_steps_reused", static_cast<double>(reused) / static_cast<double>(n));
  if (config_.outer == "ppo") {
    double loss_value = 0.0, clipped = 0.0;
    for (int64_t epoch = 0; epoch < config_.outer_epochs; ++epoch) {
      torch::Tensor loss = torch::zeros({});
      clipped = 0.0;
      for (int64_t i = 0; i < n; ++i) {
        // the first epoch is at theta; later ones re-adapt from the stepped theta
        const nn::ActionDistribution d = policy_->Forward(
            post[i].obs, {}, epoch == 0 ? adapted[i] : InnerStep(params, pre[i], ones_pre, true));
        const ClippedSurrogate s = ClippedSurrogateLoss(
            d.LogProb(post[i].actions), post[i].log_probs, post[i].advantages, config_.clip_range);
        loss = loss + s.loss / static_cast<double>(n);
        clipped += s.clip_fraction / static_cast<double>(n);
      }
      policy_->ZeroGrad();
      loss.backward();
      outer_optimizer_.Step(policy_->flat(), policy_->flat_grad());
      loss_value = loss.item<double>();
    }
    RequireFinite(policy_->flat(), "maml", "the policy's parameters");
    m.Set("outer_loss", loss_value);
    m.Set("clip_fraction", clipped);
    ++num_updates_;
    return m;
  }
  for (int64_t i = 0; i < n; ++i) {
    std::vector<torch::Tensor> detached;
    for (const torch::Tensor& p : adapted[i]) detached.push_back(p.detach());
    old.push_back(policy_->Forward(post[i].obs, {}, detached).Detached());
  }
  // one graph at theta serves the gradient and every Fisher-vector product
  torch::Tensor kl;
  const torch::Tensor surr = objective(at_theta, &kl);
  const torch::Tensor g = FlatGradient(Grad(surr, params, false), params);
  const double surr_before = surr.item<double>();
  const torch::Tensor kl_grad = FlatGradient(Grad(kl, params, true), params);
  auto fisher = [&](const torch::Tensor& v) {
    const torch::Tensor hv = FlatGradient(Grad((kl_grad * v).sum(), params, false), params);
    return hv + config_.cg_damping * v;
  };
  m.Set("surrogate", surr_before);
  // candidates re-adapt from each new theta (in grad mode: the inner step is a gradient)
  const TrustRegionResult step = TrustRegionStep(
      g, fisher, policy_->flat().clone(),
      [&](const torch::Tensor& values) {
        torch::NoGradGuard no_grad;
        policy_->flat().copy_(values);
      },
      [&] {
        torch::Tensor candidate_kl;
        const double value =
            objective([&](int64_t i) { return InnerStep(params, pre[i], ones_pre, false); },
                      &candidate_kl)
                .item<double>();
        return std::make_pair(value, candidate_kl.item<double>());
      },
      surr_before,
      {config_.max_kl, config_.cg_iters, config_.backtrack_ratio, config_.max_backtracks});
  step.WriteTo(m);
  RequireFinite(policy_->flat(), "maml", "the policy's parameters");
  ++num_updates_;
  return m;
}

void MamlLearner::Save(torch::serialize::OutputArchive& archive) const {
  WriteSignature(archive, kMamlCheckpointCode,
                 {spaces_.obs_dim, spaces_.action_dim, spaces_.num_actions});
  WriteModule(archive, "policy", *policy_);
  WriteOptimizer(archive, "outer_optimizer", outer_optimizer_);
  WriteProgress(archive, num_updates_, generator_);
}

void MamlLearner::Load(torch::serialize::InputArchive& archive) {
  if (!HasSignature(archive, kMamlCheckpointCode,
                    {spaces_.obs_dim, spaces_.action_dim, spaces_.num_actions})) {
    throw Error("maml checkpoint: not a checkpoint of MAML with these sizes");
  }
  ReadModule(archive, "policy", *policy_);
  ReadOptimizer(archive, "outer_optimizer", outer_optimizer_);
  ReadProgress(archive, num_updates_, generator_);
}

}  // namespace manyworlds::agents
