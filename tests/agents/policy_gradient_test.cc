// The on-policy family's math on hand-computed numbers (GAE with Gymnasium's
// episode flags, distributions, conjugate gradient, the linear baseline) and
// its learners' contracts (checkpoints round-trip, TRPO respects its trust
// region, PPO's clip).
#include <cmath>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/agents/ppo/ppo.h"
#include "manyworlds/agents/trpo/trpo.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/stochastic_policy.h"
#include "manyworlds/rl/generator.h"
#include "manyworlds/rl/linear_baseline.h"
#include "manyworlds/rl/rollout_buffer.h"

namespace manyworlds {
namespace {

torch::Tensor T(std::vector<float> v, int64_t rows, int64_t cols) {
  return torch::tensor(v).reshape({rows, cols});
}

TEST(GaeTest, HandComputedWithTerminationTruncationAndCut) {
  // one env, 4 steps: episode A = steps 0-1 (terminated at 1), episode B =
  // steps 2-3 (truncated at 3, final obs value 10).
  const double g = 0.9, l = 0.5;
  const torch::Tensor r = T({1, 2, 3, 4}, 4, 1);
  const torch::Tensor v = T({0.5, 1.0, 2.0, 3.0}, 4, 1);
  const torch::Tensor term = T({0, 1, 0, 0}, 4, 1);
  const torch::Tensor ended = T({0, 1, 0, 1}, 4, 1);
  const torch::Tensor boot = T({0, 0, 0, 10}, 4, 1);
  const torch::Tensor adv = rl::ComputeGae(r, v, term, ended, boot, g, l);
  const double d3 = 4 + g * 10 - 3;  // truncated: bootstraps from the final obs
  const double d2 = 3 + g * 3 - 2;
  const double d1 = 2 + 0 - 1;       // terminated: no bootstrap
  const double d0 = 1 + g * 1 - 0.5;
  EXPECT_NEAR(adv[3][0].item<float>(), d3, 1e-5);
  EXPECT_NEAR(adv[2][0].item<float>(), d2 + g * l * d3, 1e-5);
  EXPECT_NEAR(adv[1][0].item<float>(), d1, 1e-5);  // nothing carries over an episode end
  EXPECT_NEAR(adv[0][0].item<float>(), d0 + g * l * d1, 1e-5);
  // lambda = 1: discounted Monte-Carlo returns minus values
  const torch::Tensor mc = rl::ComputeGae(r, v, term, ended, boot, g, 1.0) + v;
  EXPECT_NEAR(mc[0][0].item<float>(), 1 + g * 2, 1e-5);
  EXPECT_NEAR(mc[2][0].item<float>(), 3 + g * (4 + g * 10), 1e-5);
  // a buffer whose last step leaves an episode running is refused
  const torch::Tensor open = T({0, 1, 0, 0}, 4, 1);
  EXPECT_THROW(rl::ComputeGae(r, v, term, open, boot, g, l), Error);
}

TEST(DistributionTest, GaussianAndCategoricalMatchClosedForms) {
  nn::ActionDistribution d;
  d.mean = torch::tensor({{0.5f, -1.0f}});
  d.log_std = torch::tensor({{std::log(2.0f), 0.0f}});
  const torch::Tensor a = torch::tensor({{1.5f, 0.0f}});
  const double expected = (-0.5 * 0.25 - std::log(2.0) - 0.5 * std::log(2 * M_PI)) +
                          (-0.5 * 1.0 - 0.5 * std::log(2 * M_PI));
  EXPECT_NEAR(d.LogProb(a).item<float>(), expected, 1e-5);
  EXPECT_NEAR(d.Entropy().item<float>(),
              std::log(2.0) + 1.0 + std::log(2 * M_PI), 1e-5);
  EXPECT_NEAR(d.KlTo(d).item<float>(), 0.0, 1e-6);
  nn::ActionDistribution e = d;
  e.mean = torch::tensor({{0.5f, 0.0f}});
  EXPECT_NEAR(d.KlTo(e).item<float>(), 0.5, 1e-5);  // unit std, mean shift 1

  nn::ActionDistribution c;
  c.discrete = true;
  c.logits = torch::log(torch::tensor({{0.2f, 0.3f, 0.5f}}));
  EXPECT_NEAR(c.LogProb(torch::tensor({{2.0f}})).item<float>(), std::log(0.5), 1e-6);
  EXPECT_NEAR(c.Entropy().item<float>(),
              -(0.2 * std::log(0.2) + 0.3 * std::log(0.3) + 0.5 * std::log(0.5)), 1e-5);
  EXPECT_EQ(c.Mode().item<float>(), 2.0f);
  at::Generator gen = rl::MakeGenerator(1);
  nn::ActionDistribution many;
  many.discrete = true;
  many.logits = c.logits.expand({20000, 3});
  const torch::Tensor samples = many.Sample(gen);
  EXPECT_NEAR((samples == 2.0f).to(torch::kFloat32).mean().item<float>(), 0.5, 0.02);
}

TEST(ConjugateGradientTest, SolvesASymmetricPositiveDefiniteSystem) {
  const torch::Tensor a = torch::tensor({{4.0f, 1.0f, 0.0f}, {1.0f, 3.0f, 0.5f},
                                         {0.0f, 0.5f, 2.0f}});
  const torch::Tensor b = torch::tensor({1.0f, 2.0f, 3.0f});
  const torch::Tensor x =
      agents::ConjugateGradient([&](const torch::Tensor& v) { return a.mv(v); }, b, 10);
  EXPECT_TRUE(torch::allclose(a.mv(x), b, 1e-4, 1e-4));
}

TEST(LinearBaselineTest, FitsAFunctionOfItsFeatures) {
  at::Generator gen = rl::MakeGenerator(2);
  const torch::Tensor x = torch::randn({400, 3}, gen, torch::kFloat32);
  const torch::Tensor t = torch::randint(0, 100, {400}, gen, torch::kInt64).to(torch::kFloat32);
  // y is linear in [x, x^2, t/100, ...]: the fit must be exact
  const torch::Tensor y = 2 * x.select(1, 0) - x.select(1, 2).square() + 3 * (t / 100) + 1;
  rl::LinearFeatureBaseline baseline(3);
  EXPECT_NEAR(baseline.Predict(x, t).abs().max().item<float>(), 0.0, 1e-9);  // before a fit
  baseline.Fit(x, t, y);
  EXPECT_LT((baseline.Predict(x, t) - y).abs().max().item<float>(), 1e-3);
}

agents::PolicySpaces Spaces(int64_t obs, int64_t act, int64_t n_actions, int64_t tasks) {
  agents::PolicySpaces s;
  s.obs_dim = obs;
  s.action_dim = act;
  s.num_actions = n_actions;
  s.num_tasks = tasks;
  return s;
}

// A random rollout with episodes of 5 steps.
rl::RolloutBuffer RandomRollout(agents::PolicyGradientLearner& learner, int64_t obs_dim,
                                int64_t envs, uint64_t seed) {
  at::Generator gen = rl::MakeGenerator(seed);
  rl::RolloutBuffer buffer(10, envs, obs_dim, learner.spaces().action_dim);
  buffer.task_index.copy_(torch::arange(envs) % learner.spaces().num_tasks);
  agents::ActorState state;
  for (int64_t t = 0; t < 10; ++t) {
    buffer.obs[t].copy_(torch::randn({envs, obs_dim}, gen, torch::kFloat32));
    const agents::ActOutput out =
        learner.Act(buffer.obs[t], buffer.task_index, state, agents::ActMode::kSample);
    buffer.actions[t].copy_(out.action);
    buffer.log_probs[t].copy_(out.log_prob);
    buffer.rewards[t].copy_(torch::randn({envs}, gen, torch::kFloat32));
    buffer.ended[t].fill_(t % 5 == 4 ? 1.0f : 0.0f);
    buffer.episode_steps[t].fill_(static_cast<float>(t % 5));
  }
  buffer.final_obs.copy_(torch::randn(buffer.final_obs.sizes(), gen, torch::kFloat32));
  return buffer;
}

TEST(PpoTest, UpdateMovesThePolicyWithinTheClipAndCheckpointsRoundTrip) {
  agents::PpoConfig config;
  config.hidden_dim = 16;
  config.minibatch_size = 8;
  config.epochs = 4;
  agents::PpoLearner ppo(config, Spaces(3, 2, 0, 2));
  rl::RolloutBuffer buffer = RandomRollout(ppo, 3, 4, 5);
  const torch::Tensor before = ppo.policy()->flat().clone();
  const agents::Metrics m = ppo.Update(buffer);
  EXPECT_FALSE(torch::equal(before, ppo.policy()->flat()));
  for (const char* key : {"policy_loss", "value_loss", "entropy", "approx_kl", "clip_fraction",
                          "explained_variance"}) {
    EXPECT_TRUE(m.Contains(key)) << key;
  }
  EXPECT_GE(m.Get("approx_kl"), 0.0);

  torch::serialize::OutputArchive out;
  ppo.Save(out);
  std::ostringstream bytes;
  out.save_to(bytes);
  agents::PpoLearner other(config, Spaces(3, 2, 0, 2));
  torch::serialize::InputArchive in;
  std::istringstream read(bytes.str());
  in.load_from(read);
  other.Load(in);
  EXPECT_TRUE(torch::equal(other.policy()->flat(), ppo.policy()->flat()));
  // the same next update from both (generators and optimizer state restored)
  rl::RolloutBuffer b1 = RandomRollout(ppo, 3, 4, 9);
  rl::RolloutBuffer b2 = RandomRollout(other, 3, 4, 9);
  ppo.Update(b1);
  other.Update(b2);
  EXPECT_TRUE(torch::equal(other.policy()->flat(), ppo.policy()->flat()));
  // a TRPO learner refuses a PPO checkpoint
  agents::TrpoLearner trpo(agents::TrpoConfig{}, Spaces(3, 2, 0, 2));
  torch::serialize::InputArchive again;
  std::istringstream read_again(bytes.str());
  again.load_from(read_again);
  EXPECT_THROW(trpo.Load(again), Error);
}

// An algorithm whose name starts with TRPO's letter: checkpoints carry the
// whole name, so neither takes the other's (they once carried the first
// letter only, and a TRPO checkpoint loaded into it without a word).
class TrpoVariant : public agents::TrpoLearner {
 public:
  using TrpoLearner::TrpoLearner;

 protected:
  const char* algo_name() const override { return "trpo_variant"; }
};

TEST(PolicyGradientCheckpointTest, AlgorithmsSharingAFirstLetterRefuseEachOthersCheckpoints) {
  agents::TrpoLearner trpo(agents::TrpoConfig{}, Spaces(3, 2, 0, 2));
  torch::serialize::OutputArchive out;
  trpo.Save(out);
  std::ostringstream bytes;
  out.save_to(bytes);
  TrpoVariant variant(agents::TrpoConfig{}, Spaces(3, 2, 0, 2));
  torch::serialize::InputArchive in;
  std::istringstream read(bytes.str());
  in.load_from(read);
  EXPECT_THROW(variant.Load(in), Error);
  // and TRPO still reads its own
  agents::TrpoLearner again(agents::TrpoConfig{}, Spaces(3, 2, 0, 2));
  torch::serialize::InputArchive in_again;
  std::istringstream read_again(bytes.str());
  in_again.load_from(read_again);
  EXPECT_NO_THROW(again.Load(in_again));
}

TEST(TrpoTest, AcceptedStepsStayInsideTheTrustRegion) {
  for (int64_t n_actions : {0, 3}) {
    agents::TrpoConfig config;
    config.hidden_dim = 16;
    config.max_kl = 0.005;
    config.baseline = "linear";
    agents::TrpoLearner trpo(config, Spaces(4, n_actions > 0 ? 1 : 2, n_actions, 1));
    rl::RolloutBuffer buffer = RandomRollout(trpo, 4, 6, 3);
    const agents::Metrics m = trpo.Update(buffer);
    EXPECT_LE(m.Get("kl"), config.max_kl * (1 + 1e-6));
    if (m.Get("step_accepted") == 1.0) {
      EXPECT_GT(m.Get("surrogate_after"), m.Get("surrogate"));
    }
  }
}

// Serialises a learner and loads it into `other`.
void CopyCheckpoint(const agents::PolicyGradientLearner& from, agents::PolicyGradientLearner& to) {
  torch::serialize::OutputArchive out;
  from.Save(out);
  std::ostringstream bytes;
  out.save_to(bytes);
  torch::serialize::InputArchive in;
  std::istringstream read(bytes.str());
  in.load_from(read);
  to.Load(in);
}

std::vector<torch::Tensor> ModuleValues(const agents::PolicyGradientLearner& learner) {
  std::vector<torch::Tensor> values;
  for (const nn::FlatModule* m : learner.policy_modules()) values.push_back(m->flat().clone());
  return values;
}

TEST(PolicyGradientTest, LearnedTaskConditioningsTrainWithThePolicyAndRoundTrip) {
  for (const char* arch : {"task_encoder", "moe"}) {
    for (bool pcgrad : {false, true}) {
      SCOPED_TRACE(std::string(arch) + (pcgrad ? " + pcgrad" : ""));
      agents::PpoConfig config;
      config.hidden_dim = 16;
      config.minibatch_size = 16;
      config.epochs = 2;
      config.architecture = arch;
      config.task_embedding_dim = 8;
      config.encoder_dim = 8;
      config.num_experts = 3;
      config.pcgrad = pcgrad;
      agents::PpoLearner ppo(config, Spaces(3, 2, 0, 3));
      // policy, task encoder (and the mixture)
      ASSERT_EQ(ppo.policy_modules().size(), std::string(arch) == "moe" ? 3u : 2u);
      const std::vector<torch::Tensor> before = ModuleValues(ppo);
      rl::RolloutBuffer buffer = RandomRollout(ppo, 3, 6, 5);
      const agents::Metrics m = ppo.Update(buffer);
      const std::vector<torch::Tensor> after = ModuleValues(ppo);
      for (size_t i = 0; i < before.size(); ++i) {
        EXPECT_FALSE(torch::equal(before[i], after[i])) << "module " << i << " did not train";
      }
      EXPECT_EQ(m.Contains("pcgrad_conflicts"), pcgrad);
      if (pcgrad) {
        EXPECT_GE(m.Get("pcgrad_conflicts"), 0.0);
        EXPECT_LE(m.Get("pcgrad_conflicts"), 1.0);
      }
      agents::PpoLearner other(config, Spaces(3, 2, 0, 3));
      CopyCheckpoint(ppo, other);
      rl::RolloutBuffer b1 = RandomRollout(ppo, 3, 6, 9);
      rl::RolloutBuffer b2 = RandomRollout(other, 3, 6, 9);
      ppo.Update(b1);
      other.Update(b2);
      const std::vector<torch::Tensor> x = ModuleValues(ppo), y = ModuleValues(other);
      for (size_t i = 0; i < x.size(); ++i) EXPECT_TRUE(torch::equal(x[i], y[i])) << i;
      // a checkpoint of the one-hot architecture does not load
      config.architecture = "mlp";
      agents::PpoLearner one_hot(config, Spaces(3, 2, 0, 3));
      EXPECT_THROW(CopyCheckpoint(ppo, one_hot), Error);
    }
  }
}

TEST(PolicyGradientTest, TrpoStepsTheLearnedConditioningInsideTheTrustRegion) {
  for (bool pcgrad : {false, true}) {
    agents::TrpoConfig config;
    config.hidden_dim = 16;
    config.max_kl = 0.01;
    config.architecture = "moe";
    config.task_embedding_dim = 8;
    config.encoder_dim = 8;
    config.pcgrad = pcgrad;
    agents::TrpoLearner trpo(config, Spaces(4, 2, 0, 3));
    const std::vector<torch::Tensor> before = ModuleValues(trpo);
    rl::RolloutBuffer buffer = RandomRollout(trpo, 4, 6, 3);
    const agents::Metrics m = trpo.Update(buffer);
    ASSERT_EQ(m.Get("step_accepted"), 1.0) << m.Get("backtracks");
    EXPECT_LE(m.Get("kl"), config.max_kl * (1 + 1e-6));
    EXPECT_GT(m.Get("surrogate_after"), m.Get("surrogate"));
    const std::vector<torch::Tensor> after = ModuleValues(trpo);
    for (size_t i = 0; i < before.size(); ++i) EXPECT_FALSE(torch::equal(before[i], after[i]));
    EXPECT_EQ(m.Contains("pcgrad_conflicts"), pcgrad);
  }
}

TEST(PolicyGradientTest, BadConfigsAreRefusedWithTheField) {
  agents::PpoConfig c;
  c.clip_range = 1.5;
  try {
    c.Validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("agent.clip_range"), std::string::npos);
  }
  agents::TrpoConfig t;
  t.min_std = 2.0;
  EXPECT_THROW(t.Validate(), ConfigError);
  agents::PpoConfig arch;
  arch.architecture = "transformer";
  try {
    arch.Validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("task_encoder, moe"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace manyworlds
