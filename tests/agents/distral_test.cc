// Distral: the prior terms of the task agents, distillation, per-task
// routing of rows and actions, checkpoints, and the three-task bandit.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/agents/distral/distral.h"
#include "manyworlds/core/error.h"
#include "tests/agents/learner_archive.h"

namespace manyworlds::agents {
namespace {

DistralConfig Tiny(double distral_alpha = 0.5) {
  DistralConfig c;
  c.hidden_dim = 16;
  c.num_layers = 2;
  c.distral_alpha = distral_alpha;
  c.seed = 3;
  return c;
}

Batch RandomBatch(int64_t b, int64_t num_tasks, uint64_t seed) {
  at::Generator gen = at::detail::createCPUGenerator(seed);
  Batch batch;
  batch.obs = torch::randn({b, 4}, gen, torch::kFloat32);
  batch.action = torch::rand({b, 2}, gen, torch::kFloat32) * 2 - 1;
  batch.reward = torch::randn({b}, gen, torch::kFloat32);
  batch.next_obs = torch::randn({b, 4}, gen, torch::kFloat32);
  batch.done = torch::zeros({b});
  batch.task_index = torch::randint(num_tasks, {b}, gen, torch::kInt64);
  return batch;
}

TEST(DistralConfigTest, BadValuesAreOneLineErrorsNamingTheField) {
  auto message = [](auto mutate) {
    DistralConfig c;
    mutate(c);
    try {
      c.Validate();
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([](DistralConfig&) {}), "no error");
  EXPECT_NE(message([](DistralConfig& c) { c.distral_alpha = -1; }).find("distral_alpha"),
            std::string::npos);
  EXPECT_NE(message([](DistralConfig& c) { c.act_with = "central"; }).find("'task' or"),
            std::string::npos);
  // The task agents' keys are checked by SAC's rules, named as Distral's.
  const std::string tau = message([](DistralConfig& c) { c.tau = 2; });
  EXPECT_EQ(tau.rfind("DistralConfig.tau", 0), 0u) << tau;
}

TEST(DistralTest, WithoutTheKlTermTheTaskAgentsAreIndependentSacAgents) {
  const DistralConfig c = Tiny(0.0);
  DistralLearner distral(c, 4, 2, 3);
  std::vector<std::unique_ptr<SacLearner>> alone;
  for (int64_t t = 0; t < 3; ++t) {
    alone.push_back(std::make_unique<SacLearner>(c.TaskAgentConfig(t), 4, 2, 1));
  }
  for (int i = 0; i < 3; ++i) {
    const Batch batch = RandomBatch(30, 3, 10 + i);
    distral.Update(batch);
    for (int64_t t = 0; t < 3; ++t) {
      const torch::Tensor rows = torch::nonzero(batch.task_index == t).reshape({-1});
      Batch part;
      part.obs = batch.obs.index_select(0, rows);
      part.action = batch.action.index_select(0, rows);
      part.reward = batch.reward.index_select(0, rows);
      part.next_obs = batch.next_obs.index_select(0, rows);
      part.done = batch.done.index_select(0, rows);
      part.task_index = torch::zeros({rows.numel()}, torch::kInt64);
      alone[t]->Update(part);
    }
  }
  for (int64_t t = 0; t < 3; ++t) {
    EXPECT_TRUE(torch::equal(distral.task_agent(t).actor()->trunk()->flat(),
                             alone[t]->actor()->trunk()->flat()))
        << t;
    EXPECT_TRUE(torch::equal(distral.task_agent(t).critic()->online()->flat(),
                             alone[t]->critic()->online()->flat()))
        << t;
  }
}

// A prior equal to the policy itself: (alpha + c) log pi - c log pi leaves
// the soft value, so the critic target is the plain one. A sign or weight
// error in the prior terms breaks the equality.
TEST(DistralTest, APriorEqualToThePolicyLeavesTheCriticTargetUnchanged) {
  SacConfig c = Tiny().TaskAgentConfig(0);
  // Standard deviations of at least e^-2: with the default bound (-20) an
  // untrained policy's std can be ~1e-8, where u - mean of its own float
  // sample rounds to 0 and a density recomputed from u differs from the
  // sampler's (which uses the noise directly).
  c.log_std_min = -2.0;
  SacLearner plain(c, 4, 2, 1), with_prior(c, 4, 2, 1);
  PolicyPrior self;
  self.weight = 0.7;
  self.log_prob = [&with_prior](const torch::Tensor& obs, const torch::Tensor& u) {
    const auto& actor = with_prior.actor();
    const nn::PolicyOutput out = actor->Forward(obs, {}, actor->trunk()->detached_params());
    return nn::DiagGaussianLogProb(u, out.mean, out.log_std) - nn::TanhLogAbsDetJacobian(u);
  };
  with_prior.SetPrior(self);
  Batch batch = RandomBatch(16, 1, 4);
  batch.task_index.zero_();
  const torch::Tensor y_plain = plain.CriticTarget(batch);
  const torch::Tensor y_prior = with_prior.CriticTarget(batch);
  EXPECT_TRUE(torch::allclose(y_plain, y_prior, 1e-4, 1e-5))
      << (y_plain - y_prior).abs().max().item<float>() << " " << y_plain;
  // A constant prior density K shifts every target by discount * c * (K - log pi) instead.
  PolicyPrior flat;
  flat.weight = 0.7;
  flat.log_prob = [](const torch::Tensor& obs, const torch::Tensor&) {
    return torch::full({obs.size(0)}, -3.0f);
  };
  SacLearner shifted(c, 4, 2, 1);
  shifted.SetPrior(flat);
  EXPECT_FALSE(torch::allclose(y_plain, shifted.CriticTarget(batch), 1e-3, 1e-3));
}

TEST(DistralTest, TheDistilledPolicyStartsStandardNormalAndMovesToTheTaskPolicies) {
  DistralLearner distral(Tiny(1.0), 4, 2, 3);
  const torch::Tensor obs = torch::randn({5, 4});
  const nn::PolicyOutput start = distral.distilled()->forward(obs);
  EXPECT_TRUE(torch::allclose(start.mean, torch::zeros_like(start.mean), 0, 1e-6));
  EXPECT_TRUE(torch::allclose(start.log_std, torch::zeros_like(start.log_std), 0, 1e-4));
  double first = 0.0, last = 0.0;
  for (int i = 0; i < 150; ++i) {
    const Metrics m = distral.Update(RandomBatch(30, 3, 100 + i % 5));
    ASSERT_TRUE(m.Contains("distill_kl"));
    ASSERT_TRUE(m.Contains("critic_loss"));
    if (i == 0) first = m.Get("distill_kl");
    last = m.Get("distill_kl");
  }
  EXPECT_LT(last, 0.5 * first) << first << " -> " << last;
}

TEST(DistralTest, ActRoutesRowsToTheirTaskAgentOrToTheDistilledPolicy) {
  DistralConfig c = Tiny();
  DistralLearner distral(c, 4, 2, 3);
  for (int i = 0; i < 3; ++i) distral.Update(RandomBatch(30, 3, i));
  const torch::Tensor obs = torch::randn({1, 4}).expand({3, 4}).contiguous();
  const torch::Tensor task = torch::tensor({2, 0, 1});
  const torch::Tensor act = distral.Act(obs, task, true);
  for (int64_t r = 0; r < 3; ++r) {
    EXPECT_TRUE(torch::allclose(
        act[r], distral.task_agent(task[r].item<int64_t>()).Act(obs[r], true), 1e-6, 1e-6));
  }
  EXPECT_FALSE(torch::allclose(act[0], act[1]));
  c.act_with = "distilled";
  DistralLearner central(c, 4, 2, 3);
  const torch::Tensor same = central.Act(obs, task, true);
  EXPECT_TRUE(torch::equal(same[0], same[1]));  // no task id: one action
  EXPECT_THROW(distral.Act(obs, torch::tensor({0, 1, 3}), true), Error);
}

TEST(DistralTest, SaveLoadResumesBitIdentically) {
  DistralLearner a(Tiny(), 4, 2, 3);
  for (int i = 0; i < 3; ++i) a.Update(RandomBatch(24, 3, i));
  const std::string bytes = Archive(a);
  DistralConfig other = Tiny();
  other.seed = 77;
  DistralLearner b(other, 4, 2, 3);
  Restore(b, bytes);
  EXPECT_EQ(b.num_updates(), 3);
  for (int i = 0; i < 2; ++i) {
    const Batch batch = RandomBatch(24, 3, 50 + i);
    const Metrics ma = a.Update(batch), mb = b.Update(batch);
    for (const auto& [name, value] : ma.items()) EXPECT_EQ(value, mb.Get(name)) << name;
  }
  EXPECT_EQ(Archive(a), Archive(b));
  DistralLearner four(Tiny(), 4, 2, 4);
  EXPECT_THROW(Restore(four, bytes), Error);
}

// The three-task bandit of sac_multitask_test.cc: reward -(a - target[task])^2.
TEST(DistralTest, TaskAgentsSolveTheThreeTaskBandit) {
  DistralConfig c;
  c.hidden_dim = 32;
  c.num_layers = 2;
  c.actor_lr = c.critic_lr = c.alpha_lr = c.distilled_lr = 1e-3;
  c.init_temperature = 0.1;
  // A KL weight small beside the rewards: the prior pulls each task's action
  // towards the centroid (at 0.1, by 0.08-0.1 in 800 updates).
  c.distral_alpha = 0.02;
  c.seed = 4;
  DistralLearner distral(c, 1, 1, 3);
  const float targets[3] = {-0.5f, 0.2f, 0.7f};
  const torch::Tensor target = torch::tensor({targets[0], targets[1], targets[2]});
  at::Generator gen = at::detail::createCPUGenerator(123);
  for (int step = 0; step < 800; ++step) {
    Batch batch;
    batch.task_index = torch::arange(48, torch::kInt64) % 3;
    batch.obs = torch::ones({48, 1});
    batch.next_obs = batch.obs;
    batch.action = torch::rand({48, 1}, gen, torch::kFloat32) * 2 - 1;
    batch.reward = -(batch.action.squeeze(1) - target.index_select(0, batch.task_index)).square();
    batch.done = torch::ones({48});
    distral.Update(batch);
  }
  const torch::Tensor act = distral.Act(torch::ones({3, 1}), torch::arange(3, torch::kInt64), true);
  for (int t = 0; t < 3; ++t) EXPECT_NEAR(act[t][0].item<float>(), targets[t], 0.08f) << t;
  // The distilled policy, blind to the task, sits among the task actions.
  c.act_with = "distilled";
  const nn::PolicyOutput pi0 = distral.distilled()->forward(torch::ones({1, 1}));
  const float central = std::tanh(pi0.mean.item<float>());
  EXPECT_GT(central, targets[0]);
  EXPECT_LT(central, targets[2]);
}

}  // namespace
}  // namespace manyworlds::agents
