// PEARL's learner: the product-of-Gaussians posterior, the update, the
// actor's belief over z through a trial, and checkpoints.
#include "manyworlds/agents/pearl/pearl.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>
#include <sstream>

#include "manyworlds/core/error.h"

namespace manyworlds::agents {
namespace {

constexpr int64_t kObs = 3, kAct = 2;

PearlConfig Small() {
  PearlConfig c;
  c.latent_dim = 4;
  c.hidden_dim = 32;
  c.num_layers = 2;
  c.encoder_hidden_dim = 32;
  c.encoder_num_layers = 2;
  c.seed = 3;
  return c;
}

torch::Tensor Rows(int64_t groups, int64_t rows, uint64_t seed) {
  auto g = at::detail::createCPUGenerator(seed);
  return torch::randn({groups, rows, kObs + kAct + 1}, g);
}

Batch RandomBatch(int64_t rows, uint64_t seed) {
  auto g = at::detail::createCPUGenerator(seed);
  Batch b;
  b.obs = torch::randn({rows, kObs}, g);
  b.action = torch::rand({rows, kAct}, g) * 2 - 1;
  b.reward = torch::randn({rows}, g);
  b.next_obs = torch::randn({rows, kObs}, g);
  b.done = torch::zeros({rows});
  b.task_index = torch::zeros({rows}, torch::kInt64);
  return b;
}

TEST(PearlPosteriorTest, IsTheProductOfThePerTransitionGaussians) {
  PearlLearner pearl(Small(), kObs, kAct);
  torch::NoGradGuard no_grad;
  const torch::Tensor context = Rows(1, 3, 1);
  torch::Tensor precision = torch::zeros({4}), weighted = torch::zeros({4});
  for (int64_t i = 0; i < 3; ++i) {
    const LatentBelief one = pearl.Posterior(context.narrow(1, i, 1));
    precision += 1.0 / one.var[0];
    weighted += one.mean[0] / one.var[0];
  }
  const LatentBelief all = pearl.Posterior(context);
  EXPECT_TRUE(torch::allclose(all.var[0], 1.0 / precision, 1e-5, 1e-7));
  EXPECT_TRUE(torch::allclose(all.mean[0], weighted / precision, 1e-4, 1e-6));
  // more evidence never widens the belief
  EXPECT_TRUE(
      (all.var[0] <= pearl.Posterior(context.narrow(1, 0, 1)).var[0] + 1e-7).all().item<bool>());
}

TEST(PearlPosteriorTest, WeightsDropRowsAndNoRowsGiveThePrior) {
  PearlLearner pearl(Small(), kObs, kAct);
  torch::NoGradGuard no_grad;
  const torch::Tensor context = Rows(2, 3, 2);
  const torch::Tensor weight = torch::tensor({{1.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}});
  const LatentBelief w = pearl.Posterior(context, weight);
  const LatentBelief kept =
      pearl.Posterior(torch::stack({context[0][0], context[0][2]}).unsqueeze(0));
  EXPECT_TRUE(torch::allclose(w.mean[0], kept.mean[0], 1e-5, 1e-6));
  EXPECT_TRUE(torch::allclose(w.var[0], kept.var[0], 1e-5, 1e-7));
  EXPECT_TRUE(torch::equal(w.mean[1], torch::zeros({4})));
  EXPECT_TRUE(torch::equal(w.var[1], torch::ones({4})));
}

TEST(PearlPosteriorTest, WithoutTheBottleneckZIsTheMeanOfTheOutputs) {
  PearlConfig c = Small();
  c.use_information_bottleneck = false;
  PearlLearner pearl(c, kObs, kAct);
  torch::NoGradGuard no_grad;
  const torch::Tensor context = Rows(1, 2, 4);
  const LatentBelief a = pearl.Posterior(context.narrow(1, 0, 1));
  const LatentBelief b = pearl.Posterior(context.narrow(1, 1, 1));
  const LatentBelief both = pearl.Posterior(context);
  EXPECT_TRUE(torch::allclose(both.mean, (a.mean + b.mean) / 2, 1e-5, 1e-6));
  EXPECT_TRUE(torch::equal(both.var, torch::zeros({1, 4})));
}

TEST(PearlUpdateTest, StepsEveryNetworkAndIsReproducible) {
  PearlLearner a(Small(), kObs, kAct), b(Small(), kObs, kAct);
  const Batch context = RandomBatch(4 * 8, 5);
  const Batch rl = RandomBatch(4 * 16, 6);
  torch::Tensor before;
  {
    c10::InferenceMode inference;
    before = a.Posterior(PearlLearner::ContextRows(context).reshape({4, 8, -1})).mean.clone();
  }
  const Metrics ma = a.Update(context, rl, 4);
  const Metrics mb = b.Update(context, rl, 4);
  for (const char* key : {"qf_loss", "vf_loss", "policy_loss", "kl_divergence"}) {
    ASSERT_TRUE(ma.Contains(key)) << key;
    EXPECT_TRUE(std::isfinite(ma.Get(key))) << key;
    EXPECT_DOUBLE_EQ(ma.Get(key), mb.Get(key)) << key;
  }
  EXPECT_GE(ma.Get("kl_divergence"), 0.0);
  EXPECT_EQ(a.num_updates(), 1);
  c10::InferenceMode inference;
  const torch::Tensor after =
      a.Posterior(PearlLearner::ContextRows(context).reshape({4, 8, -1})).mean;
  EXPECT_FALSE(torch::equal(before, after)) << "the encoder did not step";
}

TEST(PearlUpdateTest, RejectsBatchesThatAreNotWholeTasks) {
  PearlLearner pearl(Small(), kObs, kAct);
  EXPECT_THROW(pearl.Update(RandomBatch(10, 1), RandomBatch(12, 2), 4), Error);
  Batch wrong = RandomBatch(8, 3);
  wrong.obs = torch::zeros({8, kObs + 1});
  EXPECT_THROW(pearl.Update(wrong, RandomBatch(8, 4), 4), Error);
}

TEST(PearlActorTest, BeliefFollowsTheTrial) {
  PearlLearner pearl(Small(), kObs, kAct);
  ActorState state = pearl.Initial(2);
  EXPECT_TRUE(state.tensors["latent"].isnan().all().item<bool>());
  const torch::Tensor obs = torch::zeros({2, kObs});
  const torch::Tensor task = torch::zeros({2}, torch::kInt64);
  const ActOutput first = pearl.Act(obs, task, state, ActMode::kSample);
  ASSERT_EQ(first.action.sizes(), (std::vector<int64_t>{2, kAct}));
  EXPECT_FALSE(state.tensors["latent"].isnan().any().item<bool>());
  const torch::Tensor z = state.tensors["latent"].clone();
  // a step that ends env 1's episode: env 1 redraws z, env 0 keeps it
  StepOutcome o;
  o.obs = torch::ones({2, kObs});
  o.action = first.action;
  o.reward = torch::tensor({0.5f, -1.0f});
  o.ended = torch::tensor({0.0f, 1.0f});
  pearl.Observe(o, state);
  EXPECT_TRUE(torch::equal(state.tensors["latent"][0], z[0]));
  EXPECT_TRUE(state.tensors["latent"][1].isnan().all().item<bool>());
  ASSERT_EQ(state.lists["history"].size(), 1u);
  // Adapt: env 0's belief becomes the posterior of what it observed
  pearl.Adapt(torch::tensor({true, false}), state);
  const LatentBelief expect = pearl.Posterior(
      torch::cat({o.obs, o.action, o.reward.reshape({2, 1})}, 1).narrow(0, 0, 1).unsqueeze(0));
  EXPECT_TRUE(
      torch::allclose(state.tensors["context"][0].narrow(0, 0, 4), expect.mean[0], 1e-5, 1e-6));
  EXPECT_TRUE(
      torch::allclose(state.tensors["context"][0].narrow(0, 4, 4), expect.var[0], 1e-5, 1e-7));
  EXPECT_TRUE(
      torch::equal(state.tensors["context"][1], torch::cat({torch::zeros({4}), torch::ones({4})})));
  // a new task forgets env 0's evidence
  pearl.Reset(torch::tensor({true, false}), ResetScope::kTask, state);
  EXPECT_TRUE(
      torch::equal(state.tensors["context"][0], torch::cat({torch::zeros({4}), torch::ones({4})})));
  EXPECT_EQ(state.lists["history"][0][0][kObs + kAct + 1].item<float>(), 0.0f);
  EXPECT_EQ(state.lists["history"][0][1][kObs + kAct + 1].item<float>(), 1.0f);
}

TEST(PearlActorTest, EvaluationDrawsNeverMoveTheTrainingGenerator) {
  PearlLearner pearl(Small(), kObs, kAct);
  const torch::Tensor before = pearl.generator().get_state();
  ActorState state = pearl.Initial(3);
  pearl.Act(torch::zeros({3, kObs}), torch::zeros({3}, torch::kInt64), state, ActMode::kSample);
  EXPECT_TRUE(torch::equal(pearl.generator().get_state(), before));
}

TEST(PearlCheckpointTest, RoundTripsAndRefusesOtherSizes) {
  PearlLearner a(Small(), kObs, kAct);
  a.Update(RandomBatch(16, 1), RandomBatch(32, 2), 2);
  std::stringstream stream;
  {
    torch::serialize::OutputArchive out;
    a.Save(out);
    out.save_to(stream);
  }
  PearlLearner b(Small(), kObs, kAct);
  {
    torch::serialize::InputArchive in;
    in.load_from(stream);
    b.Load(in);
  }
  EXPECT_EQ(b.num_updates(), 1);
  const Metrics ma = a.Update(RandomBatch(16, 3), RandomBatch(32, 4), 2);
  const Metrics mb = b.Update(RandomBatch(16, 3), RandomBatch(32, 4), 2);
  EXPECT_DOUBLE_EQ(ma.Get("qf_loss"), mb.Get("qf_loss"));
  EXPECT_DOUBLE_EQ(ma.Get("policy_loss"), mb.Get("policy_loss"));

  PearlConfig other = Small();
  other.latent_dim = 5;
  PearlLearner c(other, kObs, kAct);
  stream.clear();
  stream.seekg(0);
  torch::serialize::InputArchive in;
  in.load_from(stream);
  EXPECT_THROW(c.Load(in), Error);
}

TEST(PearlConfigTest, RejectsBadFields) {
  PearlConfig c;
  c.latent_dim = 0;
  EXPECT_THROW(c.Validate(), ConfigError);
  c = PearlConfig{};
  c.prior_episodes = 0;
  c.posterior_episodes = 0;
  EXPECT_THROW(c.Validate(), ConfigError);
  c = PearlConfig{};
  c.reward_scale = std::nan("");
  EXPECT_THROW(c.Validate(), ConfigError);
  c = PearlConfig{};
  c.meta_batch = 100000;
  c.batch_size = 1000000;
  EXPECT_THROW(c.Validate(), ConfigError);
  EXPECT_NO_THROW(PearlConfig{}.Validate());
}

}  // namespace
}  // namespace manyworlds::agents
