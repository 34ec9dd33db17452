// TE-PPO's pieces on small hand-checked cases: the inference windows, the
// per-episode latent of its actor, an update and a checkpoint round trip,
// and the config errors.
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/agents/ppo/ppo.h"
#include "manyworlds/agents/te_ppo/te_ppo.h"
#include "manyworlds/core/error.h"
#include "manyworlds/rl/generator.h"
#include "manyworlds/rl/rollout_buffer.h"

namespace manyworlds {
namespace {

agents::PolicySpaces Spaces(int64_t obs, int64_t act, int64_t tasks) {
  agents::PolicySpaces s;
  s.obs_dim = obs;
  s.action_dim = act;
  s.num_tasks = tasks;
  return s;
}

agents::TePpoConfig SmallConfig() {
  agents::TePpoConfig c;
  c.hidden_dim = 16;
  c.minibatch_size = 8;
  c.epochs = 3;
  c.inference_window = 3;
  c.inference_epochs = 2;
  c.inference_minibatch_size = 8;
  c.seed = 4;
  return c;
}

TEST(TePpoTest, InferenceWindowsLookForwardAndRepeatTheLastObservationOfTheEpisode) {
  // one env, obs 1..4, episodes end at steps 1 and 3
  const torch::Tensor obs = torch::tensor({1.f, 2.f, 3.f, 4.f}).reshape({4, 1, 1});
  const torch::Tensor ended = torch::tensor({0.f, 1.f, 0.f, 1.f}).reshape({4, 1});
  const torch::Tensor w = agents::TePpoLearner::InferenceWindows(obs, ended, 3);
  const torch::Tensor expected =
      torch::tensor({1.f, 2.f, 2.f, 2.f, 2.f, 2.f, 3.f, 4.f, 4.f, 4.f, 4.f, 4.f}).reshape({4, 3});
  EXPECT_TRUE(torch::equal(w, expected)) << w;
  // two observation dimensions stay together, envs stay apart
  const torch::Tensor obs2 = torch::arange(12, torch::kFloat32).reshape({3, 2, 2});
  const torch::Tensor w2 =
      agents::TePpoLearner::InferenceWindows(obs2, torch::tensor({0.f, 0.f, 0.f, 1.f, 1.f, 1.f}).reshape({3, 2}), 2);
  // row t * N + n: env 0 at t 0 sees s_0, s_1 of env 0; env 1 at t 1 ended there
  EXPECT_TRUE(torch::equal(w2[0], torch::tensor({0.f, 1.f, 4.f, 5.f})));
  EXPECT_TRUE(torch::equal(w2[3], torch::tensor({6.f, 7.f, 6.f, 7.f})));
}

TEST(TePpoTest, TheActorHoldsOneLatentPerEpisode) {
  agents::TePpoLearner te(SmallConfig(), Spaces(3, 2, 2));
  const torch::Tensor obs = torch::zeros({4, 3});
  const torch::Tensor tasks = torch::tensor({0, 0, 1, 1}, torch::kInt64);
  agents::ActorState state = te.Initial(4);
  const torch::Tensor z1 = te.Act(obs, tasks, state, agents::ActMode::kSample).latent;
  const torch::Tensor z2 = te.Act(obs, tasks, state, agents::ActMode::kSample).latent;
  EXPECT_TRUE(torch::equal(z1, z2));  // held within the episode
  EXPECT_FALSE(torch::equal(z1[0], z1[1]));  // drawn per env, not per task
  te.Reset(torch::tensor({false, true, false, false}), agents::ResetScope::kEpisode, state);
  const torch::Tensor z3 = te.Act(obs, tasks, state, agents::ActMode::kSample).latent;
  EXPECT_TRUE(torch::equal(z3[0], z1[0]));
  EXPECT_FALSE(torch::equal(z3[1], z1[1]));  // a new episode, a new latent
  // deterministic acting uses the encoder's mean of the env's task
  agents::ActorState none;
  const torch::Tensor mean = te.Act(obs, tasks, none, agents::ActMode::kDeterministic).latent;
  EXPECT_TRUE(torch::allclose(mean[0], te.TaskLatentMeans()[0]));
  EXPECT_TRUE(torch::allclose(mean[3], te.TaskLatentMeans()[1]));
}

rl::RolloutBuffer Rollout(agents::TePpoLearner& te, uint64_t seed) {
  const int64_t envs = 4, steps = 10;
  at::Generator gen = rl::MakeGenerator(seed);
  rl::RolloutBuffer buffer(steps, envs, 3, 2);
  buffer.task_index.copy_(torch::arange(envs) % 2);
  buffer.latents = torch::zeros({steps, envs, te.config().latent_dim});
  agents::ActorState state = te.Initial(envs);
  for (int64_t t = 0; t < steps; ++t) {
    buffer.obs[t].copy_(torch::randn({envs, 3}, gen, torch::kFloat32));
    const agents::ActOutput out =
        te.Act(buffer.obs[t], buffer.task_index, state, agents::ActMode::kSample);
    buffer.actions[t].copy_(out.action);
    buffer.log_probs[t].copy_(out.log_prob);
    buffer.latents[t].copy_(out.latent);
    buffer.rewards[t].copy_(torch::randn({envs}, gen, torch::kFloat32));
    const bool end = t % 5 == 4;
    buffer.ended[t].fill_(end ? 1.0f : 0.0f);
    buffer.episode_steps[t].fill_(static_cast<float>(t % 5));
    if (end) te.Reset(torch::ones({envs}, torch::kBool), agents::ResetScope::kEpisode, state);
  }
  buffer.final_obs.copy_(torch::randn(buffer.final_obs.sizes(), gen, torch::kFloat32));
  return buffer;
}

std::string Bytes(const agents::Learner& learner) {
  torch::serialize::OutputArchive out;
  learner.Save(out);
  std::ostringstream bytes;
  out.save_to(bytes);
  return bytes.str();
}

void LoadBytes(agents::Learner& learner, const std::string& bytes) {
  torch::serialize::InputArchive in;
  std::istringstream read(bytes);
  in.load_from(read);
  learner.Load(in);
}

TEST(TePpoTest, UpdateTrainsEncoderPolicyAndInferenceAndCheckpointsRoundTrip) {
  agents::TePpoLearner te(SmallConfig(), Spaces(3, 2, 2));
  const torch::Tensor means_before = te.TaskLatentMeans();
  rl::RolloutBuffer buffer = Rollout(te, 5);
  const agents::Metrics m = te.Update(buffer);
  EXPECT_FALSE(torch::equal(means_before, te.TaskLatentMeans()));  // the surrogate reaches the encoder
  for (const char* key : {"policy_loss", "entropy", "encoder_entropy", "approx_kl",
                          "clip_fraction", "inference_loss", "inference_ce", "inference_rmse",
                          "latent_min_distance", "explained_variance"}) {
    EXPECT_TRUE(m.Contains(key)) << key;
  }
  // rewards are restored after the augmentation
  rl::RolloutBuffer fresh = Rollout(te, 6);
  const torch::Tensor rewards = fresh.rewards.clone();
  te.Update(fresh);
  EXPECT_TRUE(torch::equal(rewards, fresh.rewards));

  const std::string bytes = Bytes(te);
  agents::TePpoLearner other(SmallConfig(), Spaces(3, 2, 2));
  LoadBytes(other, bytes);
  EXPECT_TRUE(torch::equal(other.TaskLatentMeans(), te.TaskLatentMeans()));
  rl::RolloutBuffer b1 = Rollout(te, 9), b2 = Rollout(other, 9);
  te.Update(b1);
  other.Update(b2);
  EXPECT_TRUE(torch::equal(other.TaskLatentMeans(), te.TaskLatentMeans()));
  EXPECT_EQ(Bytes(other), Bytes(te));
  // a PPO learner refuses the checkpoint and TE-PPO refuses PPO's
  agents::PpoLearner ppo(agents::PpoConfig{}, Spaces(3, 2, 2));
  EXPECT_THROW(LoadBytes(ppo, bytes), Error);
  EXPECT_THROW(LoadBytes(other, Bytes(ppo)), Error);
  // a rollout without latents is refused
  rl::RolloutBuffer plain = Rollout(te, 3);
  plain.latents = torch::Tensor();
  EXPECT_THROW(te.Update(plain), Error);
}

TEST(TePpoTest, BadConfigsAreRefusedWithTheField) {
  auto error_of = [](auto mutate) {
    agents::TePpoConfig c;
    mutate(c);
    try {
      c.Validate();
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error_of([](auto& c) { c.architecture = "multihead"; }).find("agent.architecture"),
            std::string::npos);
  EXPECT_NE(error_of([](auto& c) { c.latent_dim = 0; }).find("agent.latent_dim"),
            std::string::npos);
  EXPECT_NE(error_of([](auto& c) { c.encoder_init_std = 0.5; }).find("agent.encoder_init_std"),
            std::string::npos);
  EXPECT_NE(error_of([](auto& c) { c.inference_window = 0; }).find("agent.inference_window"),
            std::string::npos);
  EXPECT_NE(error_of([](auto& c) { c.inference_ce_coeff = -1; }).find("agent.inference_ce_coeff"),
            std::string::npos);
  EXPECT_EQ(error_of([](auto&) {}), "");
}

}  // namespace
}  // namespace manyworlds
