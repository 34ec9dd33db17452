// SAC on pixel frames and SAC-AE: the convolutional encoder and decoder, the
// replay buffer's frames, the autoencoder's learning, checkpoints.
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/agents/replay_buffer.h"
#include "manyworlds/agents/sac/sac.h"
#include "manyworlds/agents/sac_ae/sac_ae.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/pixel_encoder.h"
#include "tests/agents/learner_archive.h"

namespace manyworlds::agents {
namespace {

const std::vector<int64_t> kFrames = {3, 16, 16};

SacAeConfig Tiny() {
  SacAeConfig c;
  c.hidden_dim = 32;
  c.num_layers = 1;
  c.num_conv_layers = 2;
  c.num_filters = 8;
  c.encoder_feature_dim = 16;
  c.seed = 5;
  return c;
}

// Frames of one bright 4 x 4 square on a dark background, at a position drawn per row: what
// moves is what the encoder must keep.
torch::Tensor SquareFrames(int64_t b, at::Generator& gen) {
  torch::Tensor frames = torch::full({b, 3, 16, 16}, 20, torch::kUInt8);
  const torch::Tensor pos = torch::randint(0, 13, {b, 2}, gen, torch::kInt64);
  for (int64_t i = 0; i < b; ++i) {
    const int64_t y = pos[i][0].item<int64_t>(), x = pos[i][1].item<int64_t>();
    frames[i].narrow(1, y, 4).narrow(2, x, 4).fill_(230);
  }
  return frames.reshape({b, 3 * 16 * 16});
}

Batch PixelBatch(int64_t b, uint64_t seed) {
  at::Generator gen = at::detail::createCPUGenerator(seed);
  Batch batch;
  batch.obs = torch::randn({b, 4}, gen, torch::kFloat32);
  batch.action = torch::rand({b, 2}, gen, torch::kFloat32) * 2 - 1;
  batch.reward = torch::randn({b}, gen, torch::kFloat32);
  batch.next_obs = torch::randn({b, 4}, gen, torch::kFloat32);
  batch.done = torch::zeros({b});
  batch.task_index = torch::zeros({b}, torch::kInt64);
  batch.pixels = SquareFrames(b, gen);
  batch.next_pixels = SquareFrames(b, gen);
  return batch;
}

TEST(PixelEncoderTest, ShapesFollowTheFrameSizeAndTheDecoderLandsOnIt) {
  at::Generator gen = at::detail::createCPUGenerator(1);
  for (const std::vector<int64_t>& shape :
       std::vector<std::vector<int64_t>>{{9, 84, 84}, {3, 33, 31}, {1, 16, 16}}) {
    nn::PixelEncoderOptions o;
    o.frame_shape = shape;
    o.num_layers = shape[1] == 84 ? 4 : 2;
    o.num_filters = 4;
    o.feature_dim = 7;
    nn::PixelEncoder encoder(o, gen);
    nn::PixelDecoder decoder(o, 7, gen);
    const torch::Tensor frames =
        torch::randint(0, 256, {2, shape[0], shape[1], shape[2]}, gen, torch::kUInt8);
    const torch::Tensor h = encoder->forward(frames);
    EXPECT_EQ(h.sizes(), torch::IntArrayRef({2, 7}));
    EXPECT_LT(h.abs().max().item<double>(), 1.0);  // tanh
    EXPECT_TRUE(torch::equal(h, encoder->forward(frames.reshape({2, -1}))));
    EXPECT_EQ(decoder->forward(h).sizes(), torch::IntArrayRef({2, shape[0], shape[1], shape[2]}));
  }
  // MTRL's 84 x 84 frames through 4 layers: 35 x 35 maps
  EXPECT_EQ(nn::PixelFeatureMapSide(84, 4), 35);
  EXPECT_EQ(nn::PixelFeatureMapSide(84, 2), 39);
  EXPECT_EQ(nn::PixelFeatureMapSide(84, 6), 31);
}

TEST(PixelEncoderTest, BadOptionsAndFramesAreOneLineErrors) {
  at::Generator gen = at::detail::createCPUGenerator(1);
  nn::PixelEncoderOptions o;
  o.frame_shape = {3, 8, 8};
  o.num_layers = 4;
  try {
    nn::PixelEncoder encoder(o, gen);
    FAIL() << "8 x 8 frames through 4 layers were accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("too small for 4 convolutions"), std::string::npos)
        << e.what();
  }
  o.num_layers = 1;
  nn::PixelEncoder encoder(o, gen);
  EXPECT_THROW(encoder->forward(torch::zeros({2, 3, 8, 9}, torch::kUInt8)), Error);
  o.frame_shape = {3, 8};
  EXPECT_THROW(nn::PixelEncoder(o, gen), ConfigError);
}

TEST(PixelReplayTest, FramesAreStoredSampledAndSnapshotted) {
  const int64_t p = 3 * 16 * 16;
  ReplayBuffer replay(20, 4, 2, 2, p);
  EXPECT_EQ(replay.transition_bytes(), 4 * (2 * 4 + 2 + 2) + 8 + 2 * p);
  std::vector<float> obs(4, 0.5f), action(2, 0.1f);
  for (int64_t i = 0; i < 7; ++i) {
    std::vector<uint8_t> frame(p, static_cast<uint8_t>(i)), next(p, static_cast<uint8_t>(100 + i));
    replay.Add(i % 2, obs, action, static_cast<float>(i), obs, false, frame, next);
  }
  EXPECT_THROW(replay.Add(0, obs, action, 0.0f, obs, false), Error);  // frames missing
  at::Generator gen = at::detail::createCPUGenerator(2);
  const Batch& batch = replay.Sample(8, ReplaySampling::kBalanced, gen);
  ASSERT_EQ(batch.pixels.sizes(), torch::IntArrayRef({8, p}));
  for (int64_t k = 0; k < 8; ++k) {
    // each row's frames are the ones added with its reward
    const auto i = static_cast<int64_t>(batch.reward[k].item<float>());
    EXPECT_EQ(batch.pixels[k][p - 1].item<uint8_t>(), i);
    EXPECT_EQ(batch.next_pixels[k][0].item<uint8_t>(), 100 + i);
  }
  std::stringstream snapshot;
  replay.Save(snapshot);
  const std::string bytes = snapshot.str();
  ReplayBuffer restored(20, 4, 2, 2, p);
  std::stringstream in(bytes);
  restored.Load(in);
  std::stringstream again;
  restored.Save(again);
  EXPECT_EQ(again.str(), bytes);
  // a damaged frame byte, a truncated block, a buffer without frames
  std::string damaged = bytes;
  damaged[damaged.size() - 20] ^= 1;
  std::stringstream bad(damaged);
  ReplayBuffer target(20, 4, 2, 2, p);
  try {
    target.Load(bad);
    FAIL() << "a damaged frames block was loaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frames block is corrupt"), std::string::npos)
        << e.what();
  }
  std::stringstream cut(bytes.substr(0, bytes.size() - 100));
  EXPECT_THROW(target.Load(cut), Error);
  ReplayBuffer plain(20, 4, 2, 2);
  std::stringstream plain_snapshot;
  plain.Save(plain_snapshot);
  EXPECT_THROW(target.Load(plain_snapshot), Error);
}

TEST(SacPixelTest, ActsOnFramesAndRefusesStateCheckpoints) {
  SacConfig c = Tiny();
  SacLearner learner(c, 4, 2, 1, {}, kFrames);
  at::Generator gen = at::detail::createCPUGenerator(3);
  const torch::Tensor frames = torch::randint(0, 256, {5, 3, 16, 16}, gen, torch::kUInt8);
  EXPECT_EQ(learner.Act(frames, false).sizes(), torch::IntArrayRef({5, 2}));
  EXPECT_EQ(learner.Act(frames[0], true).sizes(), torch::IntArrayRef({2}));
  EXPECT_THROW(learner.Act(torch::zeros({5, 4}), false), Error);
  // a batch without frames is refused before any step
  Batch batch = PixelBatch(8, 4);
  batch.pixels = torch::Tensor();
  EXPECT_THROW(learner.Update(batch), Error);
  SacLearner state_learner(c, 4, 2, 1);
  const std::string state_checkpoint = Archive(state_learner);
  try {
    Restore(learner, state_checkpoint);
    FAIL() << "a state checkpoint was loaded into a pixel learner";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("acts on the state, this learner on frames (3, 16, 16)"),
              std::string::npos)
        << e.what();
  }
}

TEST(SacAeConfigTest, BadValuesNameTheFieldAndFramesAreRequired) {
  SacAeConfig c = Tiny();
  c.decoder_lr = 0.0;
  try {
    SacAeLearner learner(c, 4, 2, 1, kFrames);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'agent.decoder_lr' must be finite and > 0"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(SacAeLearner(Tiny(), 4, 2, 1, {}), ConfigError);
  c = Tiny();
  c.num_conv_layers = 5;  // 16 x 16 frames are too small
  EXPECT_THROW(SacAeLearner(c, 4, 2, 1, kFrames), ConfigError);
}

// The decoder learns to draw the square where the encoder saw it: after 1500 updates the
// reconstruction error is well under that of the best constant frame (the mean frame).
TEST(SacAeTest, TheAutoencoderLearnsTheFrames) {
  SacAeLearner learner(Tiny(), 4, 2, 1, kFrames);
  const Batch probe = PixelBatch(256, 99);
  at::Generator noise = at::detail::createCPUGenerator(7);
  const torch::Tensor target = nn::PreprocessFrames(probe.pixels, noise);
  const double constant = (target - target.mean(0, true)).square().mean().item<double>();
  auto loss = [&] {
    torch::NoGradGuard no_grad;
    at::Generator g = at::detail::createCPUGenerator(7);
    return learner.AutoencoderLoss(probe, g).mean().item<double>();
  };
  const double before = loss();
  std::vector<Batch> batches;
  for (uint64_t i = 0; i < 8; ++i) batches.push_back(PixelBatch(32, 10 + i));
  Metrics last;
  for (int u = 0; u < 1500; ++u) last = learner.Update(batches[u % 8]);
  const double after = loss();
  EXPECT_TRUE(last.Contains("ae_loss"));
  EXPECT_TRUE(last.Contains("critic_loss"));
  EXPECT_GT(before, constant);
  EXPECT_LT(after, 0.5 * constant) << "before " << before << ", constant frame " << constant;
}

// PCGrad and GradNorm combine with the pixel learners (MTRL's pcgrad_sac_ae, gradnorm agents):
// SAC's critic step, encoder included, goes through them.
TEST(SacAeTest, PcGradAndGradNormCombineWithIt) {
  for (const bool gradnorm : {false, true}) {
    SacAeConfig c = Tiny();
    c.pcgrad = !gradnorm;
    c.gradnorm = gradnorm;
    SacAeLearner learner(c, 4, 2, 2, kFrames);
    Batch batch = PixelBatch(16, 30);
    batch.task_index = torch::arange(16, torch::kInt64) % 2;
    const torch::Tensor before = learner.sac().pixel_encoder()->flat().clone();
    Metrics m;
    for (int i = 0; i < 3; ++i) m = learner.Update(batch);
    EXPECT_TRUE(m.Contains(gradnorm ? "gradnorm_loss" : "pcgrad_conflicts")) << gradnorm;
    EXPECT_EQ(m.Contains("pcgrad_ae_conflicts"), !gradnorm);
    EXPECT_EQ(m.Contains("gradnorm_ae_loss"), gradnorm);
    EXPECT_TRUE(m.Contains("ae_loss"));
    EXPECT_FALSE(torch::equal(before, learner.sac().pixel_encoder()->flat()));
    if (gradnorm) {
      EXPECT_FALSE(torch::equal(learner.sac().gradnorm_weights(true), torch::ones({2})));
      // the autoencoder loss has task weights of its own, balanced too
      const torch::Tensor w = learner.gradnorm().weights;
      EXPECT_FALSE(torch::equal(w, torch::ones({2})));
      EXPECT_NEAR(w.sum().item<float>(), 2.0f, 1e-4f);
    }
  }
}

TEST(SacAeTest, ResumeFromACheckpointIsExact) {
  std::vector<Batch> batches;
  for (uint64_t i = 0; i < 6; ++i) batches.push_back(PixelBatch(16, 20 + i));
  SacAeLearner straight(Tiny(), 4, 2, 1, kFrames);
  for (const Batch& b : batches) straight.Update(b);
  SacAeLearner first(Tiny(), 4, 2, 1, kFrames);
  for (int i = 0; i < 3; ++i) first.Update(batches[i]);
  SacAeConfig other_seed = Tiny();
  other_seed.seed = 99;
  SacAeLearner resumed(other_seed, 4, 2, 1, kFrames);
  Restore(resumed, Archive(first));
  for (int i = 3; i < 6; ++i) resumed.Update(batches[i]);
  EXPECT_TRUE(torch::equal(straight.decoder()->flat(), resumed.decoder()->flat()));
  EXPECT_TRUE(torch::equal(straight.sac().pixel_encoder()->flat(),
                           resumed.sac().pixel_encoder()->flat()));
  EXPECT_TRUE(torch::equal(straight.sac().pixel_encoder_target()->flat(),
                           resumed.sac().pixel_encoder_target()->flat()));
  EXPECT_TRUE(torch::equal(straight.sac().actor()->trunk()->flat(),
                           resumed.sac().actor()->trunk()->flat()));
  // and the frames differ from a state learner's checkpoint
  SacLearner state_learner(Tiny(), 4, 2, 1);
  EXPECT_THROW(Restore(resumed, Archive(state_learner)), Error);
}

}  // namespace
}  // namespace manyworlds::agents
