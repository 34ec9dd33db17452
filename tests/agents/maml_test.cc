// MAML's learner contracts: the inner step is one vanilla policy-gradient
// step, Adapt from observed steps equals the inner step on the same data,
// adapted envs act with their own parameters, checkpoints round-trip.
#include "manyworlds/agents/maml/maml.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <ATen/CPUGeneratorImpl.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/core/error.h"
#include "manyworlds/rl/rollout_buffer.h"

namespace manyworlds::agents {
namespace {

PolicySpaces Spaces() {
  PolicySpaces s;
  s.obs_dim = 2;
  s.action_dim = 2;
  return s;
}

MamlConfig Small() {
  MamlConfig c;
  c.hidden_dim = 8;
  c.episodes_per_task = 1;
  return c;
}

TEST(MamlTest, InnerStepIsOnePolicyGradientStep) {
  MamlLearner maml(Small(), Spaces());
  MamlEpisodes e;
  e.obs = torch::randn({6, 2});
  e.actions = torch::randn({6, 2});
  e.advantages = torch::randn({6});
  const torch::Tensor w = torch::ones({6});
  const auto& theta = maml.policy()->params();
  const std::vector<torch::Tensor> adapted = maml.InnerStep(theta, e, w, false);
  // by hand: theta - lr * grad(-mean(log pi * A))
  const torch::Tensor loss =
      -(maml.policy()->Forward(e.obs).LogProb(e.actions) * e.advantages).mean();
  const auto grads = torch::autograd::grad({loss}, theta);
  for (size_t j = 0; j < theta.size(); ++j) {
    EXPECT_TRUE(torch::allclose(adapted[j], theta[j] - 0.1 * grads[j], 1e-5, 1e-6)) << j;
  }
  // rows of weight 0 do not count
  torch::Tensor half = w.clone();
  half.narrow(0, 3, 3).zero_();
  MamlEpisodes first = e;
  first.obs = e.obs.narrow(0, 0, 3);
  first.actions = e.actions.narrow(0, 0, 3);
  first.advantages = e.advantages.narrow(0, 0, 3);
  const auto masked = maml.InnerStep(theta, e, half, false);
  const auto three = maml.InnerStep(theta, first, torch::ones({3}), false);
  for (size_t j = 0; j < theta.size(); ++j) {
    EXPECT_TRUE(torch::allclose(masked[j], three[j], 1e-5, 1e-6)) << j;
  }
}

// The meta-gradient flows through the inner step: the autograd gradient of a
// post-adaptation objective F(theta) = mean log pi_{theta'(theta)}(a|s), with
// theta' = InnerStep(theta), equals central finite differences of F in every
// coordinate (in double precision, so the comparison can be tight), and the
// first-order approximation (the inner gradient treated as a constant) does
// not: the second-order term is what this checks.
TEST(MamlTest, MetaGradientThroughTheInnerStepMatchesFiniteDifferences) {
  MamlConfig config = Small();
  config.hidden_dim = 4;
  config.inner_lr = 0.5;  // large enough for the second-order term to matter
  MamlLearner maml(config, Spaces());
  at::Generator gen = at::detail::createCPUGenerator(7);
  const auto opts = torch::TensorOptions().dtype(torch::kFloat64);
  MamlEpisodes pre;
  pre.obs = torch::randn({8, 2}, gen, opts);
  pre.actions = torch::randn({8, 2}, gen, opts);
  pre.advantages = torch::randn({8}, gen, opts);
  const torch::Tensor weights = torch::ones({8}, opts);
  const torch::Tensor post_obs = torch::randn({8, 2}, gen, opts);
  const torch::Tensor post_actions = torch::randn({8, 2}, gen, opts);

  std::vector<torch::Tensor> theta;
  for (const torch::Tensor& p : maml.policy()->params()) {
    theta.push_back(p.detach().to(torch::kFloat64).requires_grad_(true));
  }
  auto objective = [&](const std::vector<torch::Tensor>& params, bool create_graph) {
    const std::vector<torch::Tensor> adapted = maml.InnerStep(params, pre, weights, create_graph);
    return maml.policy()->Forward(post_obs, {}, adapted).LogProb(post_actions).mean();
  };
  const std::vector<torch::Tensor> second_order =
      torch::autograd::grad({objective(theta, true)}, theta);
  const std::vector<torch::Tensor> first_order =
      torch::autograd::grad({objective(theta, false)}, theta, {}, {}, false, true);

  const double eps = 1e-6;
  double max_error = 0.0, max_first_order_error = 0.0, max_gradient = 0.0;
  for (size_t j = 0; j < theta.size(); ++j) {
    for (int64_t k = 0; k < theta[j].numel(); ++k) {
      auto shifted = [&](double delta) {
        std::vector<torch::Tensor> params;
        for (const torch::Tensor& p : theta) params.push_back(p.detach().clone());
        params[j].view(-1)[k] += delta;
        for (torch::Tensor& p : params) p.requires_grad_(true);
        return objective(params, true).item<double>();
      };
      const double numeric = (shifted(eps) - shifted(-eps)) / (2.0 * eps);
      const double analytic = second_order[j].reshape(-1)[k].item<double>();
      const double approx =
          first_order[j].defined() ? first_order[j].reshape(-1)[k].item<double>() : 0.0;
      max_error = std::max(max_error, std::abs(analytic - numeric));
      max_first_order_error = std::max(max_first_order_error, std::abs(approx - numeric));
      max_gradient = std::max(max_gradient, std::abs(numeric));
    }
  }
  EXPECT_GT(max_gradient, 1e-2);
  EXPECT_LT(max_error, 1e-6 * std::max(1.0, max_gradient)) << "largest |autograd - numeric|";
  EXPECT_GT(max_first_order_error, 1e-2 * max_gradient)
      << "the first-order gradient should differ when the inner step is this large";
}

TEST(MamlTest, AdaptFromObservedStepsGivesEachEnvItsOwnPolicy) {
  MamlLearner maml(Small(), Spaces());
  ActorState state;
  torch::manual_seed(3);
  const torch::Tensor tasks = torch::zeros({2}, torch::kInt64);
  std::vector<torch::Tensor> obs, actions, rewards;
  for (int t = 0; t < 4; ++t) {
    const torch::Tensor o = torch::randn({2, 2});
    const ActOutput out = maml.Act(o, tasks, state, ActMode::kSample);
    const torch::Tensor r = torch::randn({2});
    StepOutcome outcome{out.action, r, torch::full({2}, t == 3 ? 1.0f : 0.0f), o, {}};
    maml.Observe(outcome, state);
    obs.push_back(o);
    actions.push_back(out.action);
    rewards.push_back(r);
  }
  maml.Adapt(torch::ones({2}, torch::kBool), state);
  ASSERT_EQ(state.lists["adapted"].size(), maml.policy()->params().size());
  EXPECT_EQ(state.lists["adapted"][0].size(0), 2);
  // env 1's adapted parameters = the inner step on env 1's own steps
  MamlEpisodes e;
  e.obs = torch::stack(obs).select(1, 1);
  e.actions = torch::stack(actions).select(1, 1);
  const torch::Tensor r1 = torch::stack(rewards).select(1, 1);
  torch::Tensor ended = torch::zeros({4});
  ended[3] = 1.0f;
  e.advantages = maml.Advantages(e.obs, r1, ended, torch::ones({4}));
  const auto expected = maml.InnerStep(maml.policy()->params(), e, torch::ones({4}), false);
  for (size_t j = 0; j < expected.size(); ++j) {
    EXPECT_TRUE(torch::allclose(state.lists["adapted"][j][1], expected[j], 1e-5, 1e-6)) << j;
  }
  // the two envs now act differently on the same observation
  const torch::Tensor same = torch::zeros({2, 2});
  const torch::Tensor a = maml.Act(same, tasks, state, ActMode::kDeterministic).action;
  EXPECT_FALSE(torch::allclose(a[0], a[1]));
  // a new task forgets the adaptation
  maml.Reset(torch::ones({2}, torch::kBool), ResetScope::kTask, state);
  EXPECT_TRUE(state.lists["adapted"].empty());
  const torch::Tensor b = maml.Act(same, tasks, state, ActMode::kDeterministic).action;
  EXPECT_TRUE(torch::allclose(b[0], b[1]));
}

// Collects one iteration (K = 1: a pre- and a post-adaptation episode of
// `len` steps per env) into `rollout`, adapting between them as the training
// loop does; returns the Update's metrics.
Metrics TrainOneIteration(MamlLearner& maml, rl::RolloutBuffer& rollout, int64_t len,
                          bool learning, bool change_the_data) {
  const int64_t n = rollout.envs();
  ActorState state;
  state.learning = learning;
  const torch::Tensor tasks = torch::zeros({n}, torch::kInt64);
  torch::manual_seed(5);
  for (int64_t t = 0; t < 2 * len; ++t) {
    const torch::Tensor o = torch::randn({n, 2});
    const ActOutput out = maml.Act(o, tasks, state, ActMode::kSample);
    const torch::Tensor r = torch::randn({n});
    const torch::Tensor end = torch::full({n}, (t + 1) % len == 0 ? 1.0f : 0.0f);
    rollout.obs[t].copy_(o);
    rollout.actions[t].copy_(out.action);
    rollout.log_probs[t].copy_(out.log_prob);
    rollout.rewards[t].copy_(r);
    rollout.ended[t].copy_(end);
    maml.Observe(StepOutcome{out.action, r, end, o, {}}, state);
    if (t + 1 == len) maml.Adapt(torch::ones({n}, torch::kBool), state);
  }
  // an update on other pre-adaptation data than Adapt saw must not reuse it
  if (change_the_data) rollout.rewards[0][0].add_(1.0f);
  return maml.Update(rollout);
}

TEST(MamlTest, UpdateReusesTheTrainingLoopsInnerStepAndLearnsTheSame) {
  const int64_t n = 3, len = 5;
  for (const std::string outer : {"trpo", "ppo"}) {
    MamlConfig config = Small();
    config.outer = outer;
    config.outer_epochs = 2;
    MamlLearner reusing(config, Spaces()), recomputing(config, Spaces());
    rl::RolloutBuffer a(2 * len, n, 2, 2), b(2 * len, n, 2, 2);
    const Metrics with = TrainOneIteration(reusing, a, len, /*learning=*/true, false);
    const Metrics without = TrainOneIteration(recomputing, b, len, /*learning=*/false, false);
    EXPECT_EQ(with.Get("inner_steps_reused"), 1.0) << outer;
    EXPECT_EQ(without.Get("inner_steps_reused"), 0.0) << outer;
    // the same inner step, so the same meta-update
    EXPECT_TRUE(torch::equal(reusing.policy()->flat(), recomputing.policy()->flat())) << outer;
    const char* loss = outer == "trpo" ? "surrogate" : "outer_loss";
    EXPECT_EQ(with.Get(loss), without.Get(loss)) << outer;
    // changed data: recomputed, and the update follows the data it was given
    MamlLearner changed(config, Spaces());
    rl::RolloutBuffer c(2 * len, n, 2, 2);
    const Metrics m = TrainOneIteration(changed, c, len, /*learning=*/true, true);
    EXPECT_EQ(m.Get("inner_steps_reused"), 2.0 / 3.0) << outer;
    EXPECT_FALSE(torch::equal(changed.policy()->flat(), reusing.policy()->flat())) << outer;
  }
}

TEST(MamlTest, CheckpointsRoundTripAndBadConfigsNameTheField) {
  MamlLearner maml(Small(), Spaces());
  torch::serialize::OutputArchive out;
  maml.Save(out);
  std::ostringstream bytes;
  out.save_to(bytes);
  auto load = [&](Learner& learner) {
    torch::serialize::InputArchive in;
    std::istringstream read(bytes.str());
    in.load_from(read);
    learner.Load(in);
  };
  MamlConfig other_seed = Small();
  other_seed.seed = 9;
  MamlLearner other(other_seed, Spaces());
  load(other);
  EXPECT_TRUE(torch::equal(other.policy()->flat(), maml.policy()->flat()));
  PolicySpaces wider = Spaces();
  wider.obs_dim = 3;
  MamlLearner mismatched(Small(), wider);
  EXPECT_THROW(load(mismatched), Error);
  MamlConfig bad = Small();
  bad.inner_lr = -1;
  try {
    bad.Validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("agent.inner_lr"), std::string::npos);
  }
}

TEST(MamlTest, ValueNetworkBaselineFitsEachTaskFromItsInitialWeights) {
  MamlConfig c = Small();
  c.baseline = "value_network";
  c.center_advantages = false;
  c.gae_lambda = 1.0;  // advantages = returns - values
  c.discount = 0.9;
  c.value_fit_steps = 200;
  MamlLearner maml(c, Spaces());
  // four episodes of 10 steps whose rewards are a smooth function of obs
  auto episodes = [](uint64_t seed, torch::Tensor* returns) {
    torch::manual_seed(seed);
    const torch::Tensor obs = torch::rand({40, 2}) * 2 - 1;
    const torch::Tensor rewards = obs.select(1, 0) + 0.5 * obs.select(1, 1).pow(2);
    torch::Tensor ended = torch::zeros({40});
    for (int k = 9; k < 40; k += 10) ended[k] = 1.0f;
    torch::Tensor g = torch::zeros({40});
    double next = 0.0;
    for (int k = 39; k >= 0; --k) {
      if (ended[k].item<float>() > 0.5f) next = 0.0;
      next = rewards[k].item<double>() + 0.9 * next;
      g[k] = next;
    }
    *returns = g;
    return std::make_tuple(obs, rewards, ended);
  };
  torch::Tensor returns_a, returns_b;
  const auto [obs_a, rewards_a, ended_a] = episodes(1, &returns_a);
  const auto [obs_b, rewards_b, ended_b] = episodes(2, &returns_b);
  const torch::Tensor first = maml.Advantages(obs_a, rewards_a, ended_a, torch::ones({40}));
  // the fitted values explain most of the returns' variance
  const double residual = first.pow(2).mean().item<double>();
  const double variance = returns_a.var(false).item<double>();
  EXPECT_LT(residual, 0.5 * variance);
  // another task's fit in between changes nothing: every fit starts afresh
  const torch::Tensor other = maml.Advantages(obs_b, rewards_b, ended_b, torch::ones({40}));
  EXPECT_FALSE(torch::allclose(other, first));
  EXPECT_TRUE(torch::equal(maml.Advantages(obs_a, rewards_a, ended_a, torch::ones({40})), first));
  // the policy's initialisation is that of a linear-baseline learner
  MamlLearner linear(Small(), Spaces());
  EXPECT_TRUE(torch::equal(linear.policy()->flat(), maml.policy()->flat()));
  MamlConfig bad = Small();
  bad.baseline = "critic";
  EXPECT_THROW(bad.Validate(), ConfigError);
}

}  // namespace
}  // namespace manyworlds::agents
