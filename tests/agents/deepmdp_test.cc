// DeepMDP and HiP-BMDP: the latent reward model learns what the frames show, the task
// parameter lets one model tell tasks apart that the frames cannot, checkpoints resume exactly.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/agents/deepmdp/deepmdp.h"
#include "manyworlds/agents/hipbmdp/hipbmdp.h"
#include "manyworlds/core/error.h"
#include "tests/agents/learner_archive.h"

namespace manyworlds::agents {
namespace {

const std::vector<int64_t> kFrames = {3, 16, 16};

template <class Config>
Config Tiny() {
  Config c;
  c.hidden_dim = 32;
  c.num_layers = 1;
  c.num_conv_layers = 2;
  c.num_filters = 8;
  c.encoder_feature_dim = 16;
  c.transition_width = 64;
  c.reward_width = 64;
  c.task_embedding_dim = 8;
  c.seed = 5;
  return c;
}

// Frames of one bright square at a column drawn per row; the reward is the column scaled to
// [0, 1] in task 0 and reversed in task 1 (rows alternate tasks when two are asked for), so a
// model that sees only the frame cannot tell the two rewards apart.
Batch SquareBatch(int64_t b, int64_t num_tasks, uint64_t seed) {
  at::Generator gen = at::detail::createCPUGenerator(seed);
  const torch::Tensor column = torch::randint(0, 13, {b}, gen, torch::kInt64);
  torch::Tensor frames = torch::full({b, 3, 16, 16}, 20, torch::kUInt8);
  for (int64_t i = 0; i < b; ++i) {
    frames[i].narrow(1, 6, 4).narrow(2, column[i].item<int64_t>(), 4).fill_(230);
  }
  Batch batch;
  batch.task_index = torch::arange(b, torch::kInt64) % num_tasks;
  const torch::Tensor x = column.to(torch::kFloat32) / 12.0;
  batch.reward = torch::where(batch.task_index == 0, x, 1.0 - x);
  batch.obs = torch::zeros({b, 4});
  batch.next_obs = torch::zeros({b, 4});
  batch.action = torch::zeros({b, 2});
  batch.done = torch::zeros({b});
  batch.pixels = frames.reshape({b, -1});
  batch.next_pixels = batch.pixels.clone();
  return batch;
}

template <class Learner>
double TrainedRewardError(Learner& learner, int64_t num_tasks, const Batch& probe) {
  std::vector<Batch> batches;
  for (uint64_t i = 0; i < 8; ++i) batches.push_back(SquareBatch(32, num_tasks, 10 + i));
  for (int u = 0; u < 600; ++u) learner.Update(batches[u % 8]);
  return learner.RewardError(probe);
}

TEST(DeepMdpTest, TheRewardModelReadsTheSquaresColumn) {
  DeepMdpLearner learner(Tiny<DeepMdpConfig>(), 4, 2, 1, kFrames);
  const Batch probe = SquareBatch(256, 1, 99);
  const double variance = (probe.reward - probe.reward.mean()).square().mean().item<double>();
  const double error = TrainedRewardError(learner, 1, probe);
  EXPECT_LT(error, 0.2 * variance) << "reward variance " << variance;
}

// Two tasks with opposite rewards on the same frames: DeepMDP's latent has no task in it, so
// its best reward model is near the mean; HiP-BMDP's task parameter separates them.
TEST(HipBmdpTest, TheTaskParameterSeparatesTasksTheFramesCannot) {
  const Batch probe = SquareBatch(256, 2, 99);
  const double variance = (probe.reward - probe.reward.mean()).square().mean().item<double>();
  DeepMdpConfig plain = Tiny<DeepMdpConfig>();
  DeepMdpLearner deepmdp(plain, 4, 2, 2, kFrames);
  HipBmdpLearner hip(Tiny<HipBmdpConfig>(), 4, 2, 2, kFrames);
  const double without = TrainedRewardError(deepmdp, 2, probe);
  const double with = TrainedRewardError(hip, 2, probe);
  EXPECT_GT(without, 0.6 * variance) << "DeepMDP told the tasks apart without a task input?";
  EXPECT_LT(with, 0.25 * variance) << "variance " << variance << ", DeepMDP " << without;
}

TEST(HipBmdpTest, ResumeFromACheckpointIsExactAndUpdatesReportTheirLosses) {
  std::vector<Batch> batches;
  for (uint64_t i = 0; i < 6; ++i) batches.push_back(SquareBatch(16, 2, 20 + i));
  HipBmdpLearner straight(Tiny<HipBmdpConfig>(), 4, 2, 2, kFrames);
  Metrics last;
  for (const Batch& b : batches) last = straight.Update(b);
  for (const char* key : {"critic_loss", "transition_loss", "reward_loss", "ae_loss",
                          "contrastive_loss"}) {
    EXPECT_TRUE(last.Contains(key)) << key;
  }
  HipBmdpLearner first(Tiny<HipBmdpConfig>(), 4, 2, 2, kFrames);
  for (int i = 0; i < 3; ++i) first.Update(batches[i]);
  HipBmdpConfig other = Tiny<HipBmdpConfig>();
  other.seed = 77;
  HipBmdpLearner resumed(other, 4, 2, 2, kFrames);
  Restore(resumed, Archive(first));
  for (int i = 3; i < 6; ++i) resumed.Update(batches[i]);
  EXPECT_TRUE(torch::equal(straight.transition()->flat(), resumed.transition()->flat()));
  EXPECT_TRUE(torch::equal(straight.reward()->flat(), resumed.reward()->flat()));
  EXPECT_TRUE(torch::equal(straight.decoder()->flat(), resumed.decoder()->flat()));
  EXPECT_TRUE(torch::equal(straight.sac().task_encoder()->flat(),
                           resumed.sac().task_encoder()->flat()));
  EXPECT_TRUE(torch::equal(straight.sac().pixel_encoder()->flat(),
                           resumed.sac().pixel_encoder()->flat()));
}

// On held-out tasks (a meta-test's) every row reads the mean task parameter, MTRL's mean_train:
// the task index no longer changes the action; on training tasks it does.
TEST(HipBmdpTest, HeldOutTasksActWithTheMeanTaskParameter) {
  HipBmdpLearner learner(Tiny<HipBmdpConfig>(), 4, 2, 3, kFrames);
  const Batch batch = SquareBatch(2, 1, 5);
  const torch::Tensor frames = batch.pixels[0].reshape({1, 3, 16, 16}).expand({3, 3, 16, 16});
  const torch::Tensor tasks = torch::arange(3, torch::kInt64);
  Actor& actor = learner.AsActor();
  ActorState training = actor.Initial(3);
  const torch::Tensor per_task =
      actor.Act(frames, tasks, training, ActMode::kDeterministic).action.clone();
  ActorState held_out = actor.Initial(3);
  held_out.held_out_tasks = true;
  const torch::Tensor mean =
      actor.Act(frames, tasks, held_out, ActMode::kDeterministic).action.clone();
  EXPECT_FALSE(torch::allclose(per_task[0], per_task[1]));
  EXPECT_TRUE(torch::equal(mean[0], mean[1]));
  EXPECT_TRUE(torch::equal(mean[0], mean[2]));
  EXPECT_FALSE(torch::allclose(mean[0], per_task[0]));
}

// PCGrad runs through the model and decoder steps too (MTRL's pcgrad_deepmdp). With one task in
// the batch it has nothing to project: the update equals the plain one, theta's gradient
// gathered over the update's losses included.
TEST(HipBmdpTest, PcGradRunsThroughTheModelLossesAndIsPlainForOneTask) {
  HipBmdpConfig pcgrad = Tiny<HipBmdpConfig>();
  pcgrad.pcgrad = true;
  HipBmdpLearner with(pcgrad, 4, 2, 2, kFrames);
  HipBmdpLearner without(Tiny<HipBmdpConfig>(), 4, 2, 2, kFrames);
  Batch one_task = SquareBatch(16, 1, 40);  // every row task 0
  Metrics m;
  for (int i = 0; i < 2; ++i) {
    m = with.Update(one_task);
    without.Update(one_task);
  }
  for (const char* key : {"pcgrad_conflicts", "pcgrad_model_conflicts", "pcgrad_decoder_conflicts"}) {
    EXPECT_TRUE(m.Contains(key)) << key;
  }
  auto close = [](const torch::Tensor& a, const torch::Tensor& b) {
    return torch::allclose(a, b, /*rtol=*/1e-4, /*atol=*/1e-6);
  };
  EXPECT_TRUE(close(with.transition()->flat(), without.transition()->flat()));
  EXPECT_TRUE(close(with.decoder()->flat(), without.decoder()->flat()));
  EXPECT_TRUE(close(with.reward()->flat(), without.reward()->flat()));
  EXPECT_TRUE(close(with.sac().pixel_encoder()->flat(), without.sac().pixel_encoder()->flat()));
  EXPECT_TRUE(close(with.sac().task_encoder()->flat(), without.sac().task_encoder()->flat()));
  // two tasks: per-task gradients, conflicts counted
  const Batch two_tasks = SquareBatch(16, 2, 41);
  m = with.Update(two_tasks);
  EXPECT_GE(m.Get("pcgrad_model_conflicts"), 0.0);
  EXPECT_LE(m.Get("pcgrad_model_conflicts"), 1.0);
}

// GradNorm runs through the model and decoder steps too (MTRL's gradnorm_deepmdp), each with
// task weights of its own. With one task the weight stays 1 and the update is the plain one;
// with two the weights move, stay positive and sum to 2; a checkpoint carries them.
TEST(HipBmdpTest, GradNormBalancesTheModelLossesAndResumesExactly) {
  HipBmdpConfig gradnorm = Tiny<HipBmdpConfig>();
  gradnorm.gradnorm = true;
  HipBmdpLearner with(gradnorm, 4, 2, 2, kFrames);
  HipBmdpLearner without(Tiny<HipBmdpConfig>(), 4, 2, 2, kFrames);
  const Batch one_task = SquareBatch(16, 1, 40);
  Metrics m;
  for (int i = 0; i < 2; ++i) {
    m = with.Update(one_task);
    without.Update(one_task);
  }
  for (const char* key : {"gradnorm_loss", "gradnorm_model_loss", "gradnorm_decoder_loss"}) {
    EXPECT_TRUE(m.Contains(key)) << key;
  }
  auto close = [](const torch::Tensor& a, const torch::Tensor& b) {
    return torch::allclose(a, b, /*rtol=*/1e-4, /*atol=*/1e-6);
  };
  EXPECT_TRUE(close(with.transition()->flat(), without.transition()->flat()));
  EXPECT_TRUE(close(with.decoder()->flat(), without.decoder()->flat()));
  EXPECT_TRUE(close(with.sac().task_encoder()->flat(), without.sac().task_encoder()->flat()));

  gradnorm.gradnorm_lr = 1e-2;  // visible steps
  HipBmdpLearner learner(gradnorm, 4, 2, 2, kFrames);
  for (int i = 0; i < 12; ++i) learner.Update(SquareBatch(16, 2, 60 + i));
  for (const nn::GradNormState* state : {&learner.gradnorm_model(), &learner.gradnorm_decoder()}) {
    EXPECT_NEAR(state->weights.sum().item<float>(), 2.0f, 1e-4f);
    EXPECT_GT(state->weights.min().item<float>(), 0.0f);
    EXPECT_GT((state->weights - 1.0f).abs().max().item<float>(), 0.01f) << state->weights;
  }
  gradnorm.seed = 8;
  HipBmdpLearner copy(gradnorm, 4, 2, 2, kFrames);
  EXPECT_FALSE(torch::equal(copy.gradnorm_model().weights, learner.gradnorm_model().weights));
  Restore(copy, Archive(learner));
  EXPECT_TRUE(torch::equal(copy.gradnorm_model().weights, learner.gradnorm_model().weights));
  const Batch next = SquareBatch(16, 2, 99);
  const Metrics ma = learner.Update(next), mb = copy.Update(next);
  for (const auto& [name, value] : ma.items()) EXPECT_EQ(value, mb.Get(name)) << name;
  EXPECT_EQ(Archive(learner), Archive(copy));
}

TEST(HipBmdpTest, ConfigsThatCannotTrainThetaAreRefused) {
  HipBmdpConfig c = Tiny<HipBmdpConfig>();
  c.architecture = "mlp";
  EXPECT_THROW(HipBmdpLearner(c, 4, 2, 2, kFrames), ConfigError);
  c = Tiny<HipBmdpConfig>();
  c.contrastive_alpha = -1.0;
  EXPECT_THROW(HipBmdpLearner(c, 4, 2, 2, kFrames), ConfigError);
  // a contrastive loss without a task parameter the learner trains
  EXPECT_THROW(DeepMdpLearner(Tiny<DeepMdpConfig>(), 4, 2, 2, kFrames, 0.01), ConfigError);
  EXPECT_THROW(DeepMdpLearner(Tiny<DeepMdpConfig>(), 4, 2, 2, {}), ConfigError);
}

}  // namespace
}  // namespace manyworlds::agents
