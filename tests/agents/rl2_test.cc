// RL2's learner contracts: the context it builds from step outcomes, which
// boundaries reset its memory, acting equals unrolling, checkpoints.
#include "manyworlds/agents/rl2/rl2.h"

#include <sstream>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/agents/ppo/ppo.h"
#include "manyworlds/core/error.h"

namespace manyworlds::agents {
namespace {

PolicySpaces Spaces(int64_t obs, int64_t act, int64_t n_actions) {
  PolicySpaces s;
  s.obs_dim = obs;
  s.action_dim = act;
  s.num_actions = n_actions;
  return s;
}

Rl2Config Small() {
  Rl2Config c;
  c.hidden_dim = 8;
  c.episodes_per_trial = 2;
  c.context_reward_scale = 0.1;
  return c;
}

TEST(Rl2Test, ContextIsOneHotActionScaledRewardAndEpisodeEnd) {
  Rl2Learner discrete(Small(), Spaces(3, 1, 4));
  const torch::Tensor c =
      discrete.Context(torch::tensor({{2.0f}}), torch::tensor({5.0f}), torch::tensor({1.0f}));
  EXPECT_TRUE(torch::allclose(c, torch::tensor({{0.0f, 0.0f, 1.0f, 0.0f, 0.5f, 1.0f}})));
  Rl2Learner box(Small(), Spaces(3, 2, 0));
  // Box actions as the env saw them: clipped to [-1, 1]
  const torch::Tensor b =
      box.Context(torch::tensor({{3.0f, -0.5f}}), torch::tensor({-2.0f}), torch::tensor({0.0f}));
  EXPECT_TRUE(torch::allclose(b, torch::tensor({{1.0f, -0.5f, -0.2f, 0.0f}})));
}

TEST(Rl2Test, MemoryPersistsAcrossEpisodesAndResetsBetweenTrials) {
  Rl2Learner rl2(Small(), Spaces(3, 2, 0));
  ActorState state = rl2.Initial(2);
  const torch::Tensor obs = torch::ones({2, 3});
  rl2.Act(obs, torch::zeros({2}, torch::kInt64), state, ActMode::kDeterministic);
  StepOutcome outcome;
  outcome.action = torch::ones({2, 2});
  outcome.reward = torch::ones({2});
  outcome.ended = torch::ones({2});
  rl2.Observe(outcome, state);
  const torch::Tensor hidden = state.tensors["hidden"].clone();
  EXPECT_GT(hidden.abs().sum().item<float>(), 0.0f);
  rl2.Reset(torch::tensor({true, true}), ResetScope::kEpisode, state);
  EXPECT_TRUE(torch::equal(state.tensors["hidden"], hidden));  // the trial goes on
  rl2.Reset(torch::tensor({false, true}), ResetScope::kTrial, state);
  EXPECT_TRUE(torch::equal(state.tensors["hidden"][0], hidden[0]));
  EXPECT_EQ(state.tensors["hidden"][1].abs().sum().item<float>(), 0.0f);
  EXPECT_EQ(state.tensors["context"][1].abs().sum().item<float>(), 0.0f);
  EXPECT_GT(state.tensors["context"][0].abs().sum().item<float>(), 0.0f);
}

TEST(Rl2Test, UpdateTrainsAndCheckpointsRoundTripAndOthersAreRefused) {
  Rl2Learner rl2(Small(), Spaces(3, 1, 4));
  rl::RolloutBuffer buffer(6, 5, 3, 1);
  ActorState state = rl2.Initial(5);
  at::Generator gen = at::make_generator<at::CPUGeneratorImpl>(3);
  for (int64_t t = 0; t < 6; ++t) {
    buffer.obs[t].copy_(torch::randn({5, 3}, gen));
    const ActOutput out =
        rl2.Act(buffer.obs[t], torch::zeros({5}, torch::kInt64), state, ActMode::kSample);
    buffer.actions[t].copy_(out.action);
    buffer.log_probs[t].copy_(out.log_prob);
    buffer.rewards[t].copy_(buffer.actions[t].squeeze(1).eq(2).to(torch::kFloat32));
    buffer.ended[t].fill_(t % 3 == 2 ? 1.0f : 0.0f);
    StepOutcome outcome;
    outcome.action = buffer.actions[t];
    outcome.reward = buffer.rewards[t];
    outcome.ended = buffer.ended[t];
    rl2.Observe(outcome, state);
  }
  const torch::Tensor before = rl2.modules()[0]->flat().clone();
  const Metrics m = rl2.Update(buffer);
  EXPECT_FALSE(torch::equal(before, rl2.modules()[0]->flat()));
  for (const char* key : {"policy_loss", "entropy", "approx_kl", "trial_return"}) {
    EXPECT_TRUE(m.Contains(key)) << key;
  }
  EXPECT_EQ(rl2.num_updates(), 1);

  torch::serialize::OutputArchive out;
  rl2.Save(out);
  std::ostringstream bytes;
  out.save_to(bytes);
  auto load = [&](Learner& learner) {
    torch::serialize::InputArchive in;
    std::istringstream read(bytes.str());
    in.load_from(read);
    learner.Load(in);
  };
  Rl2Learner other(Small(), Spaces(3, 1, 4));
  load(other);
  EXPECT_TRUE(torch::equal(other.modules()[0]->flat(), rl2.modules()[0]->flat()));
  EXPECT_EQ(other.num_updates(), 1);
  Rl2Config wider = Small();
  wider.hidden_dim = 16;
  Rl2Learner other_size(wider, Spaces(3, 1, 4));
  EXPECT_THROW(load(other_size), Error);
  PpoLearner ppo(PpoConfig{}, Spaces(3, 1, 4));
  EXPECT_THROW(load(ppo), Error);
}

TEST(Rl2Test, BadConfigsNameTheField) {
  Rl2Config c;
  c.episodes_per_trial = 0;
  try {
    c.Validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("agent.episodes_per_trial"), std::string::npos);
  }
  c = Rl2Config{};
  c.entropy_method = "maximum";
  EXPECT_THROW(c.Validate(), ConfigError);
}

}  // namespace
}  // namespace manyworlds::agents
