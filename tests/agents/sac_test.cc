#include <algorithm>
#include <cmath>
#include <numbers>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/agents/sac/sac.h"
#include "manyworlds/agents/sac/sac_timing.h"
#include "manyworlds/core/error.h"

namespace manyworlds::agents {
namespace {

SacConfig Tiny() {
  SacConfig c;
  c.hidden_dim = 16;
  c.num_layers = 2;
  c.seed = 1;
  return c;
}

Batch RandomBatch(int64_t b, int64_t obs_dim, int64_t action_dim, int64_t num_tasks,
                  uint64_t seed) {
  at::Generator gen = at::detail::createCPUGenerator(seed);
  Batch batch;
  batch.obs = torch::randn({b, obs_dim}, gen, torch::kFloat32);
  batch.action = torch::rand({b, action_dim}, gen, torch::kFloat32) * 2 - 1;
  batch.reward = torch::randn({b}, gen, torch::kFloat32);
  batch.next_obs = torch::randn({b, obs_dim}, gen, torch::kFloat32);
  batch.done = torch::zeros({b});
  batch.task_index = torch::randint(num_tasks, {b}, gen, torch::kInt64);
  return batch;
}

TEST(SacConfigTest, DefaultsFollowMtrlAndValidateRejectsBadFields) {
  SacConfig c;
  EXPECT_EQ(c.hidden_dim, 400);
  EXPECT_EQ(c.num_layers, 3);
  EXPECT_DOUBLE_EQ(c.actor_lr, 3e-4);
  EXPECT_DOUBLE_EQ(c.discount, 0.99);
  EXPECT_DOUBLE_EQ(c.tau, 0.005);
  EXPECT_DOUBLE_EQ(c.init_temperature, 1.0);
  EXPECT_EQ(c.batch_size, 128);
  EXPECT_FALSE(c.target_entropy.has_value());
  EXPECT_NO_THROW(c.Validate());
  auto bad = [](auto mutate) {
    SacConfig c;
    mutate(c);
    return c;
  };
  EXPECT_THROW(bad([](SacConfig& c) { c.discount = 1.5; }).Validate(), ConfigError);
  EXPECT_THROW(bad([](SacConfig& c) { c.tau = 0; }).Validate(), ConfigError);
  EXPECT_THROW(bad([](SacConfig& c) { c.critic_lr = -1; }).Validate(), ConfigError);
  EXPECT_THROW(bad([](SacConfig& c) { c.init_temperature = 0; }).Validate(), ConfigError);
  EXPECT_THROW(bad([](SacConfig& c) { c.log_std_min = 3; }).Validate(), ConfigError);
  EXPECT_THROW(bad([](SacConfig& c) { c.actor_update_freq = 0; }).Validate(), ConfigError);
  EXPECT_THROW(bad([](SacConfig& c) { c.target_entropy = NAN; }).Validate(), ConfigError);
  try {
    bad([](SacConfig& c) { c.batch_size = 0; }).Validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("batch_size"), std::string::npos);
  }
  EXPECT_THROW(SacLearner(bad([](SacConfig& c) { c.tau = 2; }), 3, 1), ConfigError);
  EXPECT_THROW(SacLearner(Tiny(), 3, 0), ConfigError);
}

TEST(SacMathTest, SoftTdTargetByHand) {
  torch::Tensor y = SoftTdTarget(torch::tensor({1.0f, -0.5f, 2.0f}), torch::tensor({0.0f, 1.0f, 0.0f}),
                                 torch::tensor({3.0f, 100.0f, -1.0f}),
                                 torch::tensor({-2.0f, 5.0f, 0.5f}), torch::tensor({0.1f}), 0.9);
  // 1 + 0.9 (3 + 0.2) = 3.88; done -> -0.5; 2 + 0.9 (-1 - 0.05) = 1.055
  EXPECT_NEAR(y[0].item<float>(), 3.88f, 1e-6);
  EXPECT_NEAR(y[1].item<float>(), -0.5f, 1e-6);
  EXPECT_NEAR(y[2].item<float>(), 1.055f, 1e-6);
}

TEST(SacLearnerTest, CriticTargetOnLinearNetworksByHand) {
  // Linear actor and critics (num_layers 0) with hand-set weights.
  SacConfig c = Tiny();
  c.num_layers = 0;
  c.discount = 0.9;
  c.init_temperature = 0.5;
  SacLearner sac(c, /*obs_dim=*/1, /*action_dim=*/1);
  {
    torch::NoGradGuard no_grad;
    // Actor: mean = 0, raw log-std = -1000 -> log_std = -20 (tanh saturates).
    auto& actor = sac.actor()->trunk()->detached_params();  // w0 (1, 2), b0 (2)
    actor[0].zero_();
    actor[1].copy_(torch::tensor({0.0f, -1000.0f}));
    // Target critics: Q1 = 1 s + 2 a + 0.5, Q2 = -1 s + 0 a + 1.
    auto& target = sac.critic()->target()->detached_params();  // w0 (2, 2, 1), b0 (2, 1, 1)
    target[0].copy_(torch::tensor({1.0f, 2.0f, -1.0f, 0.0f}).view({2, 2, 1}));
    target[1].copy_(torch::tensor({0.5f, 1.0f}).view({2, 1, 1}));
  }
  Batch batch;
  batch.obs = torch::zeros({2, 1});
  batch.action = torch::zeros({2, 1});
  batch.next_obs = torch::tensor({0.5f, -2.0f}).view({2, 1});
  batch.reward = torch::tensor({1.0f, -0.5f});
  batch.done = torch::tensor({0.0f, 1.0f});
  batch.task_index = torch::zeros({2}, torch::kInt64);
  // The noise the learner will draw.
  const torch::Tensor eps = torch::randn({2, 1}, sac.generator().clone(), torch::kFloat32);
  const torch::Tensor y = sac.CriticTarget(batch);
  // a' = tanh(eps e^-20) ~ 0: min(Q1, Q2)(0.5, 0) = min(1.0, 0.5) = 0.5.
  // log pi = -eps^2/2 + 20 - log(2 pi)/2 (tanh correction ~ 0).
  const double e0 = eps[0][0].item<double>();
  const double log_pi = -0.5 * e0 * e0 + 20.0 - 0.5 * std::log(2 * std::numbers::pi);
  EXPECT_NEAR(y[0].item<double>(), 1.0 + 0.9 * (0.5 - 0.5 * log_pi), 1e-4);
  EXPECT_NEAR(y[1].item<double>(), -0.5, 1e-6);
}

TEST(SacLearnerTest, TemperatureMovesTowardTheTargetEntropy) {
  // The initial policy is nearly deterministic (log-std ~ -9), far below the
  // default target -|A|: alpha must grow. With a target far below the
  // entropy it must shrink.
  Batch batch = RandomBatch(32, 4, 2, 1, 3);
  SacLearner up(Tiny(), 4, 2);
  const double before = up.Alpha().item<double>();
  Metrics m = up.Update(batch);
  EXPECT_LT(m.Get("entropy"), up.target_entropy());
  EXPECT_LT(m.Get("alpha_loss"), 0.0);
  EXPECT_GT(up.Alpha().item<double>(), before);

  SacConfig low = Tiny();
  low.target_entropy = -1000.0;
  SacLearner down(low, 4, 2);
  Metrics m2 = down.Update(batch);
  EXPECT_GT(m2.Get("alpha_loss"), 0.0);
  EXPECT_LT(down.Alpha().item<double>(), before);
  EXPECT_NEAR(down.Alpha().item<double>(), before * std::exp(-3e-4), 1e-6);
}

TEST(SacLearnerTest, DisentangledAlphaMovesOnlyTheTasksInTheBatch) {
  SacConfig c = Tiny();
  c.disentangled_alpha = true;
  SacLearner sac(c, 4, 2, /*num_tasks=*/3);
  ASSERT_EQ(sac.Alpha().numel(), 3);
  Batch batch = RandomBatch(16, 4, 2, 3, 5);
  batch.task_index.narrow(0, 0, 8).fill_(2);
  batch.task_index.narrow(0, 8, 8).fill_(0);
  sac.Update(batch);
  torch::Tensor alpha = sac.Alpha();
  EXPECT_GT(alpha[0].item<double>(), 1.0);
  EXPECT_DOUBLE_EQ(alpha[1].item<double>(), 1.0);
  EXPECT_GT(alpha[2].item<double>(), 1.0);
  batch.task_index[0] = 3;
  EXPECT_THROW(sac.Update(batch), Error);
}

TEST(SacLearnerTest, UpdateReportsMetricsAndMovesEveryNetwork) {
  SacLearner sac(Tiny(), 5, 2);
  const torch::Tensor actor0 = sac.actor()->trunk()->flat().clone();
  const torch::Tensor critic0 = sac.critic()->online()->flat().clone();
  const torch::Tensor target0 = sac.critic()->target()->flat().clone();
  Metrics m = sac.Update(RandomBatch(8, 5, 2, 1, 7));
  for (const char* name : {"critic_loss", "q_mean", "actor_loss", "alpha", "alpha_loss", "entropy"}) {
    ASSERT_TRUE(m.Contains(name)) << name;
    EXPECT_TRUE(std::isfinite(m.Get(name))) << name;
  }
  EXPECT_FALSE(torch::equal(actor0, sac.actor()->trunk()->flat()));
  EXPECT_FALSE(torch::equal(critic0, sac.critic()->online()->flat()));
  // Polyak with tau 0.005 after the critic step.
  torch::Tensor expected = 0.995 * target0 + 0.005 * sac.critic()->online()->flat();
  EXPECT_TRUE(torch::allclose(sac.critic()->target()->flat(), expected, 1e-5, 1e-7));
  EXPECT_EQ(sac.num_updates(), 1);
  // actor_update_freq 2: the second update skips the actor.
  SacConfig c = Tiny();
  c.actor_update_freq = 2;
  SacLearner every2(c, 5, 2);
  EXPECT_TRUE(every2.Update(RandomBatch(8, 5, 2, 1, 7)).Contains("actor_loss"));
  EXPECT_FALSE(every2.Update(RandomBatch(8, 5, 2, 1, 8)).Contains("actor_loss"));
}

TEST(SacLearnerTest, ActorStepAddsNoCriticWeightGradients) {
  // After Update the critic's flat gradient must be exactly the critic-loss
  // gradient: the actor loss runs the critics on detached weights.
  SacLearner a(Tiny(), 5, 2);
  torch::serialize::OutputArchive out;
  a.Save(out);
  std::stringstream stream;
  out.save_to(stream);
  SacLearner b(Tiny(), 5, 2);
  torch::serialize::InputArchive in;
  in.load_from(stream);
  b.Load(in);
  const Batch batch = RandomBatch(16, 5, 2, 1, 9);
  a.Update(batch);
  // The same critic loss by hand on the twin (same generator state).
  const torch::Tensor y = b.CriticTarget(batch);
  const torch::Tensor q = b.critic()->forward(batch.obs, batch.action);
  b.critic()->online()->ZeroGrad();
  (2.0 * (q - y).square().mean()).backward();
  EXPECT_TRUE(torch::allclose(a.critic()->online()->flat_grad(),
                              b.critic()->online()->flat_grad(), 1e-5, 1e-7));
  EXPECT_GT(b.critic()->online()->flat_grad().abs().sum().item<float>(), 0.0f);
}

TEST(SacLearnerTest, RejectsMalformedBatches) {
  SacLearner sac(Tiny(), 5, 2);
  Batch batch = RandomBatch(8, 5, 2, 1, 7);
  batch.reward = torch::zeros({8, 1});
  EXPECT_THROW(sac.Update(batch), Error);
  batch = RandomBatch(8, 5, 2, 1, 7);
  batch.task_index = batch.task_index.to(torch::kInt32);
  EXPECT_THROW(sac.Update(batch), Error);
  batch = RandomBatch(8, 5, 2, 1, 7);
  batch.done = torch::zeros({8}, torch::kBool);
  EXPECT_NO_THROW(sac.Update(batch));
}

TEST(SacLearnerTest, ActShapesRangeAndDeterminism) {
  SacLearner sac(Tiny(), 5, 3);
  torch::Tensor obs = torch::randn({4, 5});
  torch::Tensor a = sac.Act(obs, false);
  ASSERT_EQ(a.sizes(), torch::IntArrayRef({4, 3}));
  EXPECT_LE(a.abs().max().item<float>(), 1.0f);
  EXPECT_TRUE(a.is_inference());
  EXPECT_TRUE(torch::equal(sac.Act(obs, true), sac.Act(obs, true)));
  EXPECT_EQ(sac.Act(torch::randn({5}), true).sizes(), torch::IntArrayRef({3}));
  EXPECT_THROW(sac.Act(torch::randn({4, 6}), true), Error);
  EXPECT_EQ(torch::get_num_threads(), 1);
}

TEST(SacLearnerTest, SaveLoadResumesIdentically) {
  SacConfig c = Tiny();
  c.disentangled_alpha = true;
  SacLearner a(c, 5, 2, 2);
  for (int i = 0; i < 3; ++i) a.Update(RandomBatch(8, 5, 2, 2, i));
  torch::serialize::OutputArchive out;
  a.Save(out);
  std::stringstream stream;
  out.save_to(stream);
  c.seed = 99;  // different initialisation, overwritten by the load
  SacLearner b(c, 5, 2, 2);
  torch::serialize::InputArchive in;
  in.load_from(stream);
  b.Load(in);
  EXPECT_EQ(b.num_updates(), 3);
  const Batch batch = RandomBatch(8, 5, 2, 2, 42);
  Metrics ma = a.Update(batch), mb = b.Update(batch);
  for (const auto& [name, value] : ma.items()) EXPECT_DOUBLE_EQ(value, mb.Get(name)) << name;
  EXPECT_TRUE(torch::equal(a.actor()->trunk()->flat(), b.actor()->trunk()->flat()));
  EXPECT_TRUE(torch::equal(a.critic()->target()->flat(), b.critic()->target()->flat()));
}

TEST(SacLearnerTest, ShardedUpdatesDependOnShardsNotThreads) {
  // The same update with 3 shards on 1, 2 and 3 threads: bitwise equal.
  auto run = [](int64_t shards, int64_t threads, const std::string& architecture) {
    SacConfig c = Tiny();
    c.architecture = architecture;
    c.disentangled_alpha = true;
    c.update_shards = shards;
    c.update_threads = threads;
    auto sac = std::make_unique<SacLearner>(c, 5, 2, 3);
    std::vector<Metrics> metrics;
    for (int i = 0; i < 4; ++i) metrics.push_back(sac->Update(RandomBatch(31, 5, 2, 3, i)));
    return std::make_pair(std::move(sac), metrics);
  };
  for (const std::string& arch : SacArchitectures()) {
    SCOPED_TRACE(arch);
    auto [one, m1] = run(3, 1, arch);
    EXPECT_EQ(one->update_threads(), 1);
    for (int64_t threads : {2, 3}) {
      auto [many, mm] = run(3, threads, arch);
      EXPECT_EQ(many->update_threads(), threads);
      EXPECT_TRUE(torch::equal(one->actor()->trunk()->flat(), many->actor()->trunk()->flat()));
      EXPECT_TRUE(
          torch::equal(one->critic()->online()->flat(), many->critic()->online()->flat()));
      EXPECT_TRUE(torch::equal(one->Alpha(), many->Alpha()));
      for (size_t i = 0; i < m1.size(); ++i) {
        for (const auto& [name, value] : m1[i].items()) {
          EXPECT_EQ(value, mm[i].Get(name)) << name;
        }
      }
    }
    // Unsharded: the same sums in another order, so close but not bitwise.
    auto [whole, mw] = run(1, 1, arch);
    EXPECT_EQ(whole->update_threads(), 1);
    EXPECT_TRUE(torch::allclose(one->critic()->online()->flat(),
                                whole->critic()->online()->flat(), 1e-4, 1e-5));
    EXPECT_TRUE(torch::allclose(one->actor()->trunk()->flat(), whole->actor()->trunk()->flat(),
                                1e-4, 1e-5));
    EXPECT_NEAR(m1[0].Get("critic_loss"), mw[0].Get("critic_loss"),
                1e-5 * std::abs(mw[0].Get("critic_loss")));
    EXPECT_NEAR(m1[0].Get("actor_loss"), mw[0].Get("actor_loss"),
                1e-5 * (1.0 + std::abs(mw[0].Get("actor_loss"))));
  }
  SacConfig bad = Tiny();
  bad.update_shards = 0;
  EXPECT_THROW(bad.Validate(), ConfigError);
  bad = Tiny();
  bad.update_threads = -1;
  EXPECT_THROW(bad.Validate(), ConfigError);
}

TEST(SacTimingTest, ReturnsAPositiveRate) {
  SacConfig c = Tiny();
  c.batch_size = 8;
  EXPECT_GT(TimeSacUpdates(c, 6, 2, 2, 3), 0.0);
  EXPECT_THROW(TimeSacUpdates(c, 6, 2, 2, 0), ConfigError);
  SacTimingResult r = MeasureSacUpdates(c, 6, 2, 2, 2, 3);
  ASSERT_EQ(r.samples.size(), 3u);
  std::vector<double> sorted = r.samples;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(r.updates_per_s, sorted[1]);
  EXPECT_THROW(MeasureSacUpdates(c, 6, 2, 2, 2, 0), ConfigError);
}

}  // namespace
}  // namespace manyworlds::agents
