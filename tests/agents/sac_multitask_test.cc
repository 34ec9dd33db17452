// Multi-task SAC: task conditioning per architecture, PCGrad, checkpoints,
// and a contextual bandit that needs the task id.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/agents/sac/sac.h"
#include "manyworlds/core/error.h"
#include "manyworlds/nn/gradnorm.h"
#include "manyworlds/nn/mlp.h"
#include "manyworlds/nn/paco.h"
#include "manyworlds/nn/pcgrad.h"
#include "tests/agents/learner_archive.h"

namespace manyworlds::agents {
namespace {

const std::vector<std::string>& kArchitectures = SacArchitectures();

SacConfig Tiny(const std::string& architecture, bool pcgrad = false) {
  SacConfig c;
  c.hidden_dim = 16;
  c.num_layers = 2;
  c.task_embedding_dim = 6;
  c.encoder_dim = 5;
  c.num_experts = 3;
  c.num_param_sets = 3;
  c.module_hidden = 8;
  c.routing_hidden = 8;
  c.architecture = architecture;
  c.pcgrad = pcgrad;
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

TEST(SacMultiTaskConfigTest, NewFieldsHaveDefaultsAndAreValidated) {
  SacConfig c;
  EXPECT_EQ(c.architecture, "mlp");
  EXPECT_EQ(c.task_embedding_dim, 50);
  EXPECT_EQ(c.num_experts, 4);
  EXPECT_EQ(c.encoder_dim, 50);
  EXPECT_FALSE(c.pcgrad);
  for (const std::string& arch : kArchitectures) {
    c.architecture = arch;
    EXPECT_NO_THROW(c.Validate()) << arch;
  }
  c.architecture = "multi_head";
  try {
    c.Validate();
    FAIL();
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("architecture"), std::string::npos) << msg;
    EXPECT_NE(msg.find("mlp, multihead, task_encoder, moe"), std::string::npos) << msg;
    EXPECT_NE(msg.find("multi_head"), std::string::npos) << msg;
  }
  auto message = [](auto mutate) {
    SacConfig c;
    mutate(c);
    try {
      c.Validate();
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([](SacConfig& c) { c.task_embedding_dim = 0; }).find("task_embedding_dim"),
            std::string::npos);
  EXPECT_NE(message([](SacConfig& c) { c.num_experts = 0; }).find("num_experts"),
            std::string::npos);
  EXPECT_NE(message([](SacConfig& c) { c.encoder_dim = -1; }).find("encoder_dim"),
            std::string::npos);
  EXPECT_THROW(SacLearner(Tiny("moe_v2"), 3, 1, 2), ConfigError);
}

TEST(SacMultiTaskTest, NetworkInputPerArchitecture) {
  const torch::Tensor obs = torch::randn({4, 3});
  const torch::Tensor task = torch::tensor({2, 0, 1, 2}, torch::kInt64);
  // mlp: the one-hot is appended inside the learner, and only with tasks.
  SacLearner mlp(Tiny("mlp"), 3, 2, 3);
  EXPECT_EQ(mlp.input_dim(), 6);
  EXPECT_TRUE(torch::equal(mlp.NetworkInput(obs, task),
                           torch::cat({obs, torch::one_hot(task, 3).to(torch::kFloat32)}, 1)));
  SacLearner single(Tiny("mlp"), 3, 2, 1);
  EXPECT_EQ(single.input_dim(), 3);
  EXPECT_TRUE(torch::equal(single.NetworkInput(obs, torch::zeros({4}, torch::kInt64)), obs));
  // multihead: the observation only; the task picks heads.
  SacLearner heads(Tiny("multihead"), 3, 2, 3);
  EXPECT_EQ(heads.input_dim(), 3);
  EXPECT_EQ(heads.actor()->options().num_heads, 3);
  EXPECT_EQ(heads.critic()->options().num_heads, 3);
  EXPECT_TRUE(heads.task_encoder().is_empty());
  // task_encoder: obs and the task's encoding.
  SacLearner enc(Tiny("task_encoder"), 3, 2, 3);
  EXPECT_EQ(enc.input_dim(), 3 + 6);
  torch::Tensor x = enc.NetworkInput(obs, task);
  EXPECT_TRUE(torch::equal(x.narrow(1, 0, 3), obs));
  torch::Tensor z = enc.task_encoder()->forward();
  EXPECT_TRUE(torch::allclose(x.narrow(1, 3, 6), z.index_select(0, task)));
  // moe: [mixture of the experts' encodings, task encoding].
  SacLearner moe(Tiny("moe"), 3, 2, 3);
  EXPECT_EQ(moe.input_dim(), 5 + 6);
  torch::Tensor xm = moe.NetworkInput(obs, task);
  torch::Tensor zm = moe.task_encoder()->forward();
  nn::MixtureEncoderImpl& e = *moe.encoder();
  torch::Tensor w = e.Weights(zm, e.params()).index_select(0, task);
  EXPECT_TRUE(torch::allclose(w.sum(1), torch::ones({4}), 1e-6, 1e-6));
  EXPECT_TRUE(torch::allclose(xm.narrow(1, 0, 5), e.Mix(obs, w, e.params()), 1e-5, 1e-6));
  EXPECT_TRUE(torch::allclose(xm.narrow(1, 5, 6), zm.index_select(0, task)));
  EXPECT_TRUE(torch::equal(moe.encoder()->flat(), moe.encoder_target()->flat()));
}

TEST(SacMultiTaskTest, TaskTrunksSeeTheBareObservationAndActPerTask) {
  for (const char* arch : {"soft_modular", "paco", "moore"}) {
    SacLearner sac(Tiny(arch), 3, 2, 3);
    EXPECT_EQ(sac.input_dim(), 3) << arch;
    EXPECT_TRUE(sac.actor()->trunk()->uses_task()) << arch;
    EXPECT_TRUE(sac.critic()->online()->uses_task()) << arch;
    EXPECT_TRUE(sac.task_encoder().is_empty()) << arch;
    const torch::Tensor obs = torch::randn({1, 3}).expand({3, 3});
    const torch::Tensor act = sac.Act(obs, torch::arange(3, torch::kInt64), true);
    // Soft Modularization starts with near-uniform routing (logits drawn
    // from U(+-3e-3)): its tasks differ, but only slightly.
    EXPECT_FALSE(torch::equal(act[0], act[1])) << arch;
  }
  EXPECT_EQ(kArchitectures.size(), 7u);
}

TEST(SacMultiTaskTest, TaskReweightWeighsTasksBySoftmaxOfMinusLogAlpha) {
  SacConfig c = Tiny("soft_modular");
  c.task_reweight = true;
  EXPECT_THROW(c.Validate(), ConfigError);  // needs per-task temperatures
  c.disentangled_alpha = true;
  SacConfig plain = c;
  plain.task_reweight = false;
  // Equal temperatures: every weight is T / T = 1, the update is the plain one.
  SacLearner a(c, 4, 2, 3), b(plain, 4, 2, 3);
  const Batch batch = RandomBatch(24, 4, 2, 3, 5);
  const Metrics ma = a.Update(batch), mb = b.Update(batch);
  EXPECT_NEAR(ma.Get("critic_loss"), mb.Get("critic_loss"), 1e-5 * std::abs(mb.Get("critic_loss")));
  // After temperatures part, the weighted loss differs from the plain one on
  // the same networks.
  for (int i = 0; i < 30; ++i) {
    const Batch more = RandomBatch(24, 4, 2, 3, 10 + i);
    a.Update(more);
    b.Update(more);
  }
  const torch::Tensor alpha = a.Alpha();
  EXPECT_GT((alpha.max() - alpha.min()).item<float>(), 1e-4f);
  EXPECT_FALSE(torch::allclose(a.critic()->online()->flat(), b.critic()->online()->flat()));
}

TEST(SacMultiTaskTest, PacoMasksAndResetsATaskWhoseLossExplodes) {
  SacConfig c = Tiny("paco");
  // Above the untrained critics' own loss (PaCo's task weights start
  // unnormalised, so its Q values start at tens), far below task 2's.
  c.paco_reset_threshold = 2e4;
  SacLearner sac(c, 4, 2, 3);
  Batch batch = RandomBatch(30, 4, 2, 3, 6);
  batch.task_index = torch::arange(30, torch::kInt64) % 3;
  // Task 2's rewards are huge: its TD error is far above the threshold.
  batch.reward = torch::where(batch.task_index == 2, torch::full({30}, 1000.0f), batch.reward);
  const Metrics m = sac.Update(batch);
  EXPECT_EQ(m.Get("paco_resets"), 1.0);
  // The masked update: the critic loss counts the other two tasks only.
  EXPECT_LT(m.Get("critic_loss"), 2e4);
  for (nn::TrunkImpl* trunk : {sac.actor()->trunk().get(), sac.critic()->online().get()}) {
    const torch::Tensor w = dynamic_cast<nn::PacoTrunkImpl&>(*trunk).task_weights();
    for (int64_t e = 0; e < w.size(0); ++e) {
      // Row 2 is a convex combination of rows 0 and 1: solve for it.
      const torch::Tensor basis = w[e].narrow(0, 0, 2).t();  // (K, 2)
      const torch::Tensor coef =
          std::get<0>(torch::linalg_lstsq(basis, w[e][2].unsqueeze(1))).squeeze(1);
      EXPECT_TRUE(torch::allclose(torch::matmul(basis, coef), w[e][2], 1e-4, 1e-5));
      EXPECT_NEAR(coef.sum().item<float>(), 1.0f, 1e-3f);
      EXPECT_GE(coef.min().item<float>(), -1e-3f);
    }
  }
  // Without the spike nothing is reset.
  SacLearner calm(c, 4, 2, 3);
  batch.reward = torch::zeros({30});
  EXPECT_EQ(calm.Update(batch).Get("paco_resets"), 0.0);
  c.paco_reset_threshold = 0.0;
  SacLearner off(c, 4, 2, 3);
  EXPECT_FALSE(off.Update(batch).Contains("paco_resets"));
}

TEST(SacMultiTaskTest, TaskMetadataVectorsReplaceTheLearnedTableAndTravelInCheckpoints) {
  SacConfig c = Tiny("moe");
  c.task_metadata = "vectors.json";  // read by the caller; the learner takes the tensor
  const torch::Tensor vectors = torch::randn({3, 7}, at::detail::createCPUGenerator(2));
  EXPECT_THROW(SacLearner(c, 4, 2, 3), ConfigError);  // set but no vectors given
  SacLearner a(c, 4, 2, 3, vectors);
  ASSERT_TRUE(torch::equal(a.task_encoder()->pretrained(), vectors));
  // Encode is the projection of the fixed vectors: P -> ReLU -> Linear -> ReLU
  // -> Linear -> ReLU -> MLP.
  const std::vector<torch::Tensor>& p = a.task_encoder()->detached_params();
  torch::Tensor h = torch::relu(vectors);
  h = torch::relu(torch::addmm(p[1], h, p[0]));
  h = torch::relu(torch::addmm(p[3], h, p[2]));
  std::vector<torch::Tensor> mlp(p.begin() + 4, p.end());
  EXPECT_TRUE(torch::allclose(a.task_encoder()->Encode(p), nn::MlpForward(h, mlp), 1e-6, 1e-6));
  for (int i = 0; i < 3; ++i) a.Update(RandomBatch(12, 4, 2, 3, i));
  EXPECT_TRUE(torch::equal(a.task_encoder()->pretrained(), vectors));  // never trained
  const std::string bytes = Archive(a);
  SacLearner b(c, 4, 2, 3, vectors);
  Restore(b, bytes);
  const Batch batch = RandomBatch(12, 4, 2, 3, 9);
  EXPECT_EQ(a.Update(batch).Get("critic_loss"), b.Update(batch).Get("critic_loss"));
  // Other vectors, or none, are refused with the reason.
  SacLearner other(c, 4, 2, 3, vectors + 1.0f);
  try {
    Restore(other, bytes);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("task metadata vectors differ"), std::string::npos)
        << e.what();
  }
  SacLearner plain(Tiny("moe"), 4, 2, 3);
  EXPECT_THROW(Restore(plain, bytes), Error);
  c.architecture = "mlp";
  EXPECT_THROW(c.Validate(), ConfigError);  // only task_encoder and moe read it
}

// The rule on hand-made numbers: task 0 has twice the gradient norm and has
// trained as fast as task 1 (alpha 1): its target is the mean, it is above
// it, so its weight's gradient is positive (the weight goes down) and task
// 1's negative. Then task 1 trains slower (its loss ratio doubles): its
// target rises with it.
TEST(GradNormTest, WeightsMoveTowardsEqualWeightedNormsScaledByTheTrainingRate) {
  const torch::Tensor w = torch::ones({3});
  const torch::Tensor present = torch::tensor({true, true, false});
  torch::Tensor initial = torch::full({3}, std::nan(""));
  nn::GradNormTerms t = nn::GradNormGradient(w, torch::tensor({4.0f, 2.0f, 0.0f}),
                                             torch::tensor({2.0f, 1.0f, 9.0f}), present,
                                             initial, 1.0);
  EXPECT_TRUE(torch::allclose(initial.narrow(0, 0, 2), torch::tensor({4.0f, 2.0f})));
  EXPECT_TRUE(std::isnan(initial[2].item<float>()));  // absent: no reference yet
  EXPECT_NEAR(t.grad[0].item<float>(), 2.0f / 2, 1e-6f);    // sign(+) * 2 / 2 tasks
  EXPECT_NEAR(t.grad[1].item<float>(), -1.0f / 2, 1e-6f);   // sign(-) * 1 / 2
  EXPECT_EQ(t.grad[2].item<float>(), 0.0f);
  EXPECT_NEAR(t.loss, (0.5 + 0.5) / 2, 1e-6);  // |2 - 1.5| and |1 - 1.5|
  // Task 1's loss ratio 2, task 0's 1: inverse rates 2/3 and 4/3; targets
  // 1.5 * (2/3) = 1 and 1.5 * (4/3) = 2; weighted norms 2 and 1.
  t = nn::GradNormGradient(w, torch::tensor({4.0f, 4.0f, 0.0f}), torch::tensor({2.0f, 1.0f, 9.0f}),
                           present, initial, 1.0);
  EXPECT_GT(t.grad[0].item<float>(), 0.0f);
  EXPECT_LT(t.grad[1].item<float>(), 0.0f);
  EXPECT_NEAR(t.loss, (1.0 + 1.0) / 2, 1e-5);
  torch::Tensor weights = torch::tensor({-1.0f, 2.0f, 4.0f});
  nn::RenormaliseTaskWeights(weights);
  EXPECT_NEAR(weights.sum().item<float>(), 3.0f, 1e-5f);
  EXPECT_GT(weights[0].item<float>(), 0.0f);
}

TEST(SacMultiTaskTest, GradNormBalancesTheTasksGradientNorms) {
  SacConfig c = Tiny("mlp");
  c.gradnorm = true;
  SacConfig bad = c;
  bad.architecture = "multihead";
  EXPECT_THROW(bad.Validate(), ConfigError);  // its last layer is per task
  bad = c;
  bad.pcgrad = true;
  EXPECT_THROW(bad.Validate(), ConfigError);
  // Weights 1 at the start: the first update is the plain one.
  SacConfig plain_config = Tiny("mlp");
  SacLearner gn(c, 4, 2, 3), plain(plain_config, 4, 2, 3);
  const Batch first = RandomBatch(30, 4, 2, 3, 1);
  const Metrics m = gn.Update(first);
  plain.Update(first);
  EXPECT_TRUE(torch::allclose(gn.critic()->online()->flat(), plain.critic()->online()->flat(),
                              1e-5, 1e-6));
  EXPECT_TRUE(m.Contains("gradnorm_loss"));
  EXPECT_TRUE(m.Contains("gradnorm_actor_loss"));
  // With a visible learning rate the weights move, stay positive and sum to 3.
  c.gradnorm_lr = 1e-2;
  SacLearner learner(c, 4, 2, 3);
  for (int i = 0; i < 30; ++i) {
    Batch batch = RandomBatch(30, 4, 2, 3, 100 + i);
    batch.reward = torch::where(batch.task_index == 0, 20.0 * batch.reward, batch.reward);
    learner.Update(batch);
  }
  for (bool critic : {true, false}) {
    const torch::Tensor w = learner.gradnorm_weights(critic);
    EXPECT_NEAR(w.sum().item<float>(), 3.0f, 1e-4f);
    EXPECT_GT(w.min().item<float>(), 0.0f);
    EXPECT_GT((w - 1.0f).abs().max().item<float>(), 0.05f) << w;
  }
  // Exact resume, GradNorm's weights, references and optimisers included.
  const std::string bytes = Archive(learner);
  c.seed = 5;
  SacLearner copy(c, 4, 2, 3);
  Restore(copy, bytes);
  const Batch next = RandomBatch(30, 4, 2, 3, 999);
  const Metrics ma = learner.Update(next), mb = copy.Update(next);
  for (const auto& [name, value] : ma.items()) EXPECT_EQ(value, mb.Get(name)) << name;
  EXPECT_EQ(Archive(learner), Archive(copy));
}

TEST(SacMultiTaskTest, ActTakesTaskIndices) {
  for (const std::string& arch : kArchitectures) {
    SacLearner sac(Tiny(arch), 3, 2, 3);
    const torch::Tensor obs = torch::randn({5, 3});
    const torch::Tensor task = torch::tensor({0, 1, 2, 1, 0}, torch::kInt64);
    torch::Tensor a = sac.Act(obs, task, false);
    ASSERT_EQ(a.sizes(), torch::IntArrayRef({5, 2})) << arch;
    EXPECT_LE(a.abs().max().item<float>(), 1.0f);
    // Deterministic, batched = row by row, and the task matters.
    torch::Tensor det = sac.Act(obs, task, true);
    for (int64_t b = 0; b < 5; ++b) {
      EXPECT_TRUE(torch::allclose(det[b], sac.Act(obs[b], task.narrow(0, b, 1), true), 1e-5,
                                  1e-6))
          << arch;
    }
    const torch::Tensor same = obs[0].expand({3, 3});
    torch::Tensor per_task = sac.Act(same, torch::arange(3, torch::kInt64), true);
    EXPECT_FALSE(arch == "soft_modular" ? torch::equal(per_task[0], per_task[1])
                                        : torch::allclose(per_task[0], per_task[1]))
        << arch;
    EXPECT_THROW(sac.Act(obs, torch::full({5}, 3, torch::kInt64), true), Error) << arch;
    EXPECT_THROW(sac.Act(obs, task.to(torch::kInt32), true), Error) << arch;
    EXPECT_THROW(sac.Act(obs, true), Error) << arch;  // single-task form
    SacLearner one(Tiny(arch), 3, 2, 1);
    EXPECT_TRUE(torch::equal(one.Act(obs, true),
                             one.Act(obs, torch::zeros({5}, torch::kInt64), true)));
  }
}

TEST(SacMultiTaskTest, EveryArchitectureUpdatesItsNetworks) {
  for (const std::string& arch : kArchitectures) {
    for (bool pcgrad : {false, true}) {
      SacLearner sac(Tiny(arch, pcgrad), 4, 2, 3);
      const torch::Tensor actor0 = sac.actor()->trunk()->flat().clone();
      const torch::Tensor critic0 = sac.critic()->online()->flat().clone();
      Metrics m = sac.Update(RandomBatch(24, 4, 2, 3, 3));
      for (const char* name :
           {"critic_loss", "q_mean", "actor_loss", "alpha", "alpha_loss", "entropy"}) {
        ASSERT_TRUE(m.Contains(name)) << arch << " " << name;
        EXPECT_TRUE(std::isfinite(m.Get(name))) << arch << " " << name;
      }
      EXPECT_EQ(m.Contains("pcgrad_conflicts"), pcgrad) << arch;
      if (pcgrad) {
        EXPECT_GE(m.Get("pcgrad_conflicts"), 0.0);
        EXPECT_LE(m.Get("pcgrad_conflicts"), 1.0);
        EXPECT_TRUE(m.Contains("pcgrad_actor_conflicts"));
      }
      EXPECT_FALSE(torch::equal(actor0, sac.actor()->trunk()->flat())) << arch;
      EXPECT_FALSE(torch::equal(critic0, sac.critic()->online()->flat())) << arch;
      if (arch == "moe") {
        // The target encoder follows by Polyak.
        EXPECT_FALSE(torch::equal(sac.encoder()->flat(), sac.encoder_target()->flat()));
      }
    }
  }
}

TEST(SacMultiTaskTest, TaskEncoderIsTrainedByTheCriticLossOnly) {
  for (const std::string& arch : {std::string("task_encoder"), std::string("moe")}) {
    // Tasks 0 and 1 in the batch, task 2 absent.
    SacLearner sac(Tiny(arch), 4, 2, 3);
    Batch batch = RandomBatch(16, 4, 2, 3, 4);
    batch.task_index = torch::arange(16, torch::kInt64) % 2;
    const torch::Tensor embedding0 = sac.task_encoder()->embedding().detach().clone();
    sac.Update(batch);
    const torch::Tensor embedding1 = sac.task_encoder()->embedding().detach();
    EXPECT_FALSE(torch::equal(embedding0[0], embedding1[0])) << arch;
    EXPECT_FALSE(torch::equal(embedding0[1], embedding1[1])) << arch;
    EXPECT_TRUE(torch::equal(embedding0[2], embedding1[2])) << arch;

    // The gradient by hand: the critic loss reaches the embedding of the
    // tasks in the batch; the actor's input is detached.
    nn::TaskEncoderImpl& enc = *sac.task_encoder();
    enc.ZeroGrad();
    const torch::Tensor y = sac.CriticTarget(batch);
    const torch::Tensor q = sac.critic()->forward(sac.NetworkInput(batch.obs, batch.task_index),
                                                  batch.action);
    (2.0 * (q - y).square().mean()).backward();
    const torch::Tensor grad = enc.embedding().grad();
    EXPECT_GT(grad[0].abs().sum().item<float>(), 0.0f) << arch;
    EXPECT_EQ(grad[2].abs().sum().item<float>(), 0.0f) << arch;
  }
}

TEST(SacMultiTaskTest, PcGradCombinesPerTaskCriticGradients) {
  // After Update the critic's flat gradient holds the combined gradient; a
  // twin (same state) recomputes the per-task gradients by hand.
  SacLearner a(Tiny("mlp", /*pcgrad=*/true), 4, 2, 3);
  SacLearner b(Tiny("mlp", /*pcgrad=*/true), 4, 2, 3);
  Restore(b, Archive(a));
  Batch batch = RandomBatch(30, 4, 2, 3, 6);
  a.Update(batch);
  const torch::Tensor y = b.CriticTarget(batch);
  const torch::Tensor q = b.critic()->forward(b.NetworkInput(batch.obs, batch.task_index),
                                              batch.action);
  auto& online = dynamic_cast<nn::EnsembleMlpImpl&>(*b.critic()->online());
  std::vector<torch::Tensor> rows;
  for (int64_t t = 0; t < 3; ++t) {
    const torch::Tensor mask = (batch.task_index == t).to(torch::kFloat32);
    const torch::Tensor loss = ((q - y).square().sum(0) * mask).sum() / mask.sum();
    online.ZeroGrad();
    loss.backward({}, /*retain_graph=*/true);
    rows.push_back(online.flat_grad().clone());
  }
  const nn::PcGradResult expected =
      nn::ProjectConflictingGradients(torch::stack(rows), b.generator());
  EXPECT_TRUE(torch::allclose(a.critic()->online()->flat_grad(), expected.gradient, 1e-4, 1e-6));
  // It differs from the plain mean-loss gradient when tasks conflict.
  if (expected.projections > 0) {
    EXPECT_FALSE(torch::allclose(expected.gradient, torch::stack(rows).mean(0), 1e-4, 1e-6));
  }
}

TEST(SacMultiTaskTest, PcGradWithOneTaskEqualsThePlainUpdate) {
  SacLearner plain(Tiny("multihead"), 4, 2, 3);
  SacLearner pc(Tiny("multihead", /*pcgrad=*/true), 4, 2, 3);
  Batch batch = RandomBatch(16, 4, 2, 3, 8);
  batch.task_index.fill_(1);
  plain.Update(batch);
  Metrics m = pc.Update(batch);
  EXPECT_EQ(m.Get("pcgrad_conflicts"), 0.0);
  EXPECT_TRUE(torch::allclose(plain.critic()->online()->flat(), pc.critic()->online()->flat(),
                              1e-5, 1e-7));
  EXPECT_TRUE(torch::allclose(plain.actor()->trunk()->flat(), pc.actor()->trunk()->flat(), 1e-5,
                              1e-7));
}

TEST(SacMultiTaskTest, SaveLoadResumesBitIdenticallyForEveryVariant) {
  for (const std::string& arch : kArchitectures) {
    for (bool pcgrad : {false, true}) {
      SacConfig c = Tiny(arch, pcgrad);
      c.disentangled_alpha = true;
      SacLearner a(c, 4, 2, 3);
      for (int i = 0; i < 3; ++i) a.Update(RandomBatch(12, 4, 2, 3, i));
      const std::string bytes = Archive(a);
      c.seed = 99;  // different initialisation and generator, overwritten by the load
      SacLearner b(c, 4, 2, 3);
      Restore(b, bytes);
      EXPECT_EQ(b.num_updates(), 3);
      for (int i = 0; i < 2; ++i) {
        const Batch batch = RandomBatch(12, 4, 2, 3, 40 + i);
        Metrics ma = a.Update(batch), mb = b.Update(batch);
        for (const auto& [name, value] : ma.items()) {
          EXPECT_EQ(value, mb.Get(name)) << arch << " pcgrad " << pcgrad << " " << name;
        }
      }
      const torch::Tensor obs = torch::randn({3, 4});
      const torch::Tensor task = torch::arange(3, torch::kInt64);
      EXPECT_TRUE(torch::equal(a.Act(obs, task, false), b.Act(obs, task, false))) << arch;
      // Every saved piece matches exactly.
      EXPECT_EQ(Archive(a), Archive(b)) << arch << " pcgrad " << pcgrad;
    }
  }
}

TEST(SacMultiTaskTest, LoadRejectsAnotherArchitectureOrTaskCount) {
  SacLearner moe(Tiny("moe"), 4, 2, 3);
  const std::string bytes = Archive(moe);
  SacLearner enc(Tiny("task_encoder"), 4, 2, 3);
  try {
    Restore(enc, bytes);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'moe'"), std::string::npos) << e.what();
  }
  SacLearner four(Tiny("moe"), 4, 2, 4);
  EXPECT_THROW(Restore(four, bytes), Error);
}

// A one-step contextual bandit: the observation is constant, the reward is
// -(a - target[task])^2. The best action depends on the task alone, so a
// learner must use the task index; without it the best single action is the
// mean target (expected reward -(a - mean)^2 - var).
constexpr float kTargets[3] = {-0.5f, 0.2f, 0.7f};

// Trains `sac` on uniform behaviour actions; with `hide_task` the learner
// sees task 0 for every sample (but rewards still follow the true task).
void TrainBandit(SacLearner& sac, bool hide_task, int steps = 800) {
  at::Generator gen = at::detail::createCPUGenerator(123);
  const torch::Tensor targets = torch::tensor({kTargets[0], kTargets[1], kTargets[2]});
  const int64_t b = 48;
  for (int step = 0; step < steps; ++step) {
    Batch batch;
    const torch::Tensor task = torch::randint(3, {b}, gen, torch::kInt64);
    batch.task_index = hide_task ? torch::zeros({b}, torch::kInt64) : task;
    batch.obs = torch::ones({b, 1});
    batch.next_obs = batch.obs;
    batch.action = torch::rand({b, 1}, gen, torch::kFloat32) * 2 - 1;
    batch.reward = -(batch.action.squeeze(1) - targets.index_select(0, task)).square();
    batch.done = torch::ones({b});
    sac.Update(batch);
  }
}

SacConfig BanditConfig(const std::string& architecture, bool pcgrad = false) {
  SacConfig c;
  c.hidden_dim = 32;
  c.num_layers = 2;
  c.actor_lr = c.critic_lr = c.alpha_lr = 1e-3;
  c.init_temperature = 0.1;
  c.disentangled_alpha = true;
  c.architecture = architecture;
  c.pcgrad = pcgrad;
  c.task_embedding_dim = 8;
  c.encoder_dim = 8;
  c.module_hidden = 32;
  c.routing_hidden = 32;
  c.seed = 4;
  return c;
}

// steps: the routed and composed architectures start (nearly) task-blind
// and need longer to tell the tasks apart.
void ExpectSolvesBandit(const std::string& arch, bool pcgrad, int steps = 800) {
  SacLearner sac(BanditConfig(arch, pcgrad), /*obs_dim=*/1, /*action_dim=*/1, /*num_tasks=*/3);
  TrainBandit(sac, /*hide_task=*/false, steps);
  const torch::Tensor act =
      sac.Act(torch::ones({3, 1}), torch::arange(3, torch::kInt64), /*deterministic=*/true);
  for (int t = 0; t < 3; ++t) {
    EXPECT_NEAR(act[t][0].item<float>(), kTargets[t], 0.08f) << arch << " task " << t;
  }
}

TEST(SacBanditTest, MlpSolvesTheThreeTaskBandit) { ExpectSolvesBandit("mlp", false); }
TEST(SacBanditTest, MultiHeadSolvesTheThreeTaskBandit) { ExpectSolvesBandit("multihead", false); }
TEST(SacBanditTest, TaskEncoderSolvesTheThreeTaskBandit) {
  ExpectSolvesBandit("task_encoder", false);
}
TEST(SacBanditTest, MoeSolvesTheThreeTaskBandit) { ExpectSolvesBandit("moe", false); }
TEST(SacBanditTest, CareWithTaskVectorsSolvesTheThreeTaskBandit) {
  SacConfig c = BanditConfig("moe");
  c.task_metadata = "vectors";
  // Three fixed unit vectors stand for the embedded descriptions.
  const torch::Tensor vectors = torch::nn::functional::normalize(
      torch::randn({3, 16}, at::detail::createCPUGenerator(11)),
      torch::nn::functional::NormalizeFuncOptions().dim(1));
  SacLearner sac(c, 1, 1, 3, vectors);
  TrainBandit(sac, /*hide_task=*/false);
  const torch::Tensor act = sac.Act(torch::ones({3, 1}), torch::arange(3, torch::kInt64), true);
  for (int t = 0; t < 3; ++t) EXPECT_NEAR(act[t][0].item<float>(), kTargets[t], 0.08f) << t;
}
TEST(SacBanditTest, PcGradSolvesTheThreeTaskBandit) { ExpectSolvesBandit("mlp", true); }
// With the bandit's constant observation, 2 modules per layer left tasks 1
// and 2 with identical routing (their embedding units dead under the ReLU)
// and one action; 4 modules (the authors' deeper configuration) separate
// all three.
TEST(SacBanditTest, SoftModularSolvesTheThreeTaskBandit) {
  SacConfig c = BanditConfig("soft_modular");
  c.num_modules = 4;
  SacLearner sac(c, /*obs_dim=*/1, /*action_dim=*/1, /*num_tasks=*/3);
  TrainBandit(sac, /*hide_task=*/false, 2000);
  const torch::Tensor act = sac.Act(torch::ones({3, 1}), torch::arange(3, torch::kInt64), true);
  for (int t = 0; t < 3; ++t) EXPECT_NEAR(act[t][0].item<float>(), kTargets[t], 0.08f) << t;
}
TEST(SacBanditTest, PacoSolvesTheThreeTaskBandit) { ExpectSolvesBandit("paco", false, 1500); }
TEST(SacBanditTest, MooreSolvesTheThreeTaskBandit) { ExpectSolvesBandit("moore", false); }

TEST(SacBanditTest, WithoutTheTaskIdTheBestIsTheMeanTarget) {
  SacLearner sac(BanditConfig("mlp"), 1, 1, 3);
  TrainBandit(sac, /*hide_task=*/true);
  const float mean = (kTargets[0] + kTargets[1] + kTargets[2]) / 3;
  // The same action whatever the task index the learner is given ...
  const torch::Tensor act = sac.Act(torch::ones({1, 1}), torch::zeros({1}, torch::kInt64), true);
  const float a = act.item<float>();
  EXPECT_NEAR(a, mean, 0.08f);
  // ... so it misses the outer tasks by about |target - mean|.
  EXPECT_GT(std::abs(a - kTargets[0]), 0.5f);
  EXPECT_GT(std::abs(a - kTargets[2]), 0.4f);
}

}  // namespace
}  // namespace manyworlds::agents
