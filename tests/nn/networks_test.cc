#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/gaussian_policy.h"
#include "manyworlds/nn/mlp.h"
#include "manyworlds/nn/pcgrad.h"
#include "manyworlds/nn/task_encoder.h"
#include "manyworlds/nn/twin_critic.h"

namespace manyworlds::nn {
namespace {

MlpOptions Small(int64_t in, int64_t out, int64_t ensemble = 1) {
  MlpOptions o;
  o.input_dim = in;
  o.output_dim = out;
  o.hidden_dim = 16;
  o.num_layers = 2;
  o.ensemble_size = ensemble;
  return o;
}

// Reference MLP with the given weights ([in, out] layout) on torch::nn::Linear.
torch::Tensor LinearStack(const torch::Tensor& x, const std::vector<torch::Tensor>& params) {
  torch::Tensor h = x;
  for (size_t i = 0; i < params.size(); i += 2) {
    h = torch::nn::functional::linear(h, params[i].t(), params[i + 1].reshape({-1}));
    if (i + 2 < params.size()) h = torch::relu(h);
  }
  return h;
}

TEST(MlpTest, ShapesAndParameterCount) {
  Mlp mlp(Small(5, 3));
  EXPECT_EQ(mlp->num_params(), 5 * 16 + 16 + 16 * 16 + 16 + 16 * 3 + 3);
  EXPECT_EQ(mlp->params().size(), 6u);
  EXPECT_EQ(mlp->parameters().size(), 6u);
  EXPECT_EQ(mlp->forward(torch::randn({7, 5})).sizes(), torch::IntArrayRef({7, 3}));
}

TEST(MlpTest, ParametersAreViewsOfOneFlatBuffer) {
  Mlp mlp(Small(4, 2));
  const float* base = mlp->flat().data_ptr<float>();
  int64_t offset = 0;
  for (const torch::Tensor& p : mlp->params()) {
    EXPECT_TRUE(p.requires_grad());
    EXPECT_TRUE(p.is_leaf());
    EXPECT_EQ(p.data_ptr<float>(), base + offset);
    EXPECT_EQ(p.grad().data_ptr<float>(), mlp->flat_grad().data_ptr<float>() + offset);
    offset += p.numel();
  }
  EXPECT_EQ(offset, mlp->num_params());
  // Writing the flat buffer changes the parameters, and the other way round.
  mlp->flat().fill_(0.5f);
  EXPECT_EQ(mlp->params()[2].view(-1)[3].item<float>(), 0.5f);
  {
    torch::NoGradGuard no_grad;
    mlp->params()[1].fill_(-2.0f);
  }
  EXPECT_EQ(mlp->flat()[mlp->params()[0].numel()].item<float>(), -2.0f);
}

TEST(MlpTest, BackwardAccumulatesIntoFlatGrad) {
  Mlp mlp(Small(3, 2));
  torch::Tensor x = torch::randn({6, 3});
  mlp->ZeroGrad();
  mlp->forward(x).square().sum().backward();
  // Reference gradients from autograd on independent copies.
  std::vector<torch::Tensor> copies;
  for (const torch::Tensor& p : mlp->params()) copies.push_back(p.detach().clone().requires_grad_());
  mlp->Forward(x, copies).square().sum().backward();
  std::vector<torch::Tensor> grads;
  for (const torch::Tensor& c : copies) grads.push_back(c.grad().reshape({-1}));
  EXPECT_TRUE(torch::allclose(mlp->flat_grad(), torch::cat(grads), 1e-5, 1e-6));
  // A second backward accumulates; ZeroGrad clears (and survives zero_grad).
  mlp->forward(x).square().sum().backward();
  EXPECT_TRUE(torch::allclose(mlp->flat_grad(), 2 * torch::cat(grads), 1e-5, 1e-6));
  mlp->zero_grad(/*set_to_none=*/true);
  mlp->ZeroGrad();
  EXPECT_EQ(mlp->flat_grad().abs().sum().item<float>(), 0.0f);
  mlp->forward(x).square().sum().backward();
  EXPECT_TRUE(torch::allclose(mlp->flat_grad(), torch::cat(grads), 1e-5, 1e-6));
}

TEST(MlpTest, FunctionalForwardEqualsModuleForwardAndLinearReference) {
  torch::manual_seed(3);
  Mlp mlp(Small(5, 3));
  torch::Tensor x = torch::randn({9, 5});
  torch::Tensor y = mlp->forward(x);
  EXPECT_TRUE(torch::equal(y, mlp->Forward(x, mlp->params())));
  EXPECT_TRUE(torch::equal(y, mlp->Forward(x, mlp->detached_params())));
  EXPECT_TRUE(torch::allclose(y, LinearStack(x, mlp->detached_params()), 1e-5, 1e-6));
  // Fast weights: a functional step differs from the module and is differentiable.
  std::vector<torch::Tensor> fast;
  for (const torch::Tensor& p : mlp->params()) fast.push_back(p - 0.1 * torch::ones_like(p));
  torch::Tensor y_fast = mlp->Forward(x, fast);
  EXPECT_FALSE(torch::allclose(y, y_fast));
  EXPECT_TRUE(y_fast.requires_grad());
}

TEST(MlpTest, DetachedParamsGiveInputGradsButNoWeightGrads) {
  Mlp mlp(Small(4, 1));
  torch::Tensor x = torch::randn({3, 4}, torch::requires_grad());
  mlp->ZeroGrad();
  mlp->Forward(x, mlp->detached_params()).sum().backward();
  EXPECT_TRUE(x.grad().defined());
  EXPECT_GT(x.grad().abs().sum().item<float>(), 0.0f);
  EXPECT_EQ(mlp->flat_grad().abs().sum().item<float>(), 0.0f);
}

TEST(MlpTest, OrthogonalInitAndZeroBias) {
  Mlp mlp(Small(20, 4));
  const torch::Tensor w0 = mlp->params()[0];  // (20, 16): orthonormal columns
  EXPECT_TRUE(torch::allclose(w0.t().mm(w0), torch::eye(16), 1e-4, 1e-5));
  const torch::Tensor w2 = mlp->params()[4];  // (16, 4)
  EXPECT_TRUE(torch::allclose(w2.t().mm(w2), torch::eye(4), 1e-4, 1e-5));
  EXPECT_EQ(mlp->params()[1].abs().sum().item<float>(), 0.0f);
}

TEST(MlpTest, SameGeneratorSeedSameWeights) {
  Mlp a(Small(3, 2), at::detail::createCPUGenerator(7));
  Mlp b(Small(3, 2), at::detail::createCPUGenerator(7));
  Mlp c(Small(3, 2), at::detail::createCPUGenerator(8));
  EXPECT_TRUE(torch::equal(a->flat(), b->flat()));
  EXPECT_FALSE(torch::equal(a->flat(), c->flat()));
}

TEST(MlpTest, SaveLoadCopiesIntoTheFlatBuffer) {
  Mlp a(Small(3, 2));
  Mlp b(Small(3, 2));
  std::stringstream stream;
  torch::save(a, stream);
  const float* before = b->flat().data_ptr<float>();
  torch::load(b, stream);
  EXPECT_EQ(b->flat().data_ptr<float>(), before);
  EXPECT_EQ(b->params()[0].data_ptr<float>(), before);
  EXPECT_TRUE(torch::equal(a->flat(), b->flat()));
}

TEST(MlpTest, RejectsBadOptions) {
  EXPECT_THROW(Mlp(Small(0, 2)), ConfigError);
  MlpOptions o = Small(2, 2);
  o.num_layers = -1;
  EXPECT_THROW(Mlp{o}, ConfigError);
}

TEST(EnsembleMlpTest, BatchedProductEqualsSeparateLinearStacks) {
  torch::manual_seed(5);
  EnsembleMlp ens(Small(6, 1, /*ensemble=*/2));
  torch::Tensor x = torch::randn({11, 6});
  torch::Tensor y = ens->forward(x);  // (2, 11, 1)
  ASSERT_EQ(y.sizes(), torch::IntArrayRef({2, 11, 1}));
  for (int64_t e = 0; e < 2; ++e) {
    std::vector<torch::Tensor> member;
    for (const torch::Tensor& p : ens->detached_params()) member.push_back(p[e]);
    EXPECT_TRUE(torch::allclose(y[e], LinearStack(x, member), 1e-5, 1e-6)) << "member " << e;
  }
  // Per-member inputs.
  torch::Tensor xs = torch::randn({2, 4, 6});
  torch::Tensor ys = ens->forward(xs);
  for (int64_t e = 0; e < 2; ++e) {
    std::vector<torch::Tensor> member;
    for (const torch::Tensor& p : ens->detached_params()) member.push_back(p[e]);
    EXPECT_TRUE(torch::allclose(ys[e], LinearStack(xs[e], member), 1e-5, 1e-6));
  }
}

TEST(EnsembleMlpTest, LargeBatchesRunPerMemberWithTheSameValuesAndGradients) {
  // At kEnsembleSplitRows rows and above the members run one addmm chain
  // each; values and weight gradients match the batched product's.
  torch::manual_seed(6);
  EnsembleMlp ens(Small(5, 2, /*ensemble=*/2));
  const int64_t rows = kEnsembleSplitRows;
  torch::Tensor x = torch::randn({rows + 1, 5});
  torch::Tensor split = ens->forward(x);
  ASSERT_EQ(split.sizes(), torch::IntArrayRef({2, rows + 1, 2}));
  split.square().sum().backward();
  const torch::Tensor split_grad = ens->flat_grad().clone();
  ens->ZeroGrad();
  // The batched path, fed in chunks below the threshold.
  std::vector<torch::Tensor> chunks;
  for (const torch::Tensor& part : x.split(rows / 2)) chunks.push_back(ens->forward(part));
  torch::Tensor batched = torch::cat(chunks, 1);
  batched.square().sum().backward();
  EXPECT_TRUE(torch::allclose(split, batched, 1e-5, 1e-6));
  EXPECT_TRUE(torch::allclose(split_grad, ens->flat_grad(), 1e-4, 1e-5));
  // Per-member inputs take the same path.
  torch::Tensor xs = torch::randn({2, rows, 5});
  torch::Tensor ys = ens->forward(xs);
  for (int64_t e = 0; e < 2; ++e) {
    std::vector<torch::Tensor> member;
    for (const torch::Tensor& p : ens->detached_params()) member.push_back(p[e]);
    EXPECT_TRUE(torch::allclose(ys[e], LinearStack(xs[e], member), 1e-5, 1e-6));
  }
}

TEST(TwinCriticTest, TargetStartsEqualAndFollowsByPolyak) {
  TwinCriticOptions o;
  o.obs_dim = 3;
  o.action_dim = 2;
  o.hidden_dim = 8;
  o.num_layers = 1;
  TwinCritic critic(o);
  EXPECT_TRUE(torch::equal(critic->online()->flat(), critic->target()->flat()));
  EXPECT_NE(critic->online()->flat().data_ptr(), critic->target()->flat().data_ptr());
  for (const torch::Tensor& p : critic->target()->params()) EXPECT_FALSE(p.requires_grad());
  torch::Tensor obs = torch::randn({5, 3});
  torch::Tensor act = torch::rand({5, 2});
  torch::Tensor q = critic->forward(obs, act);
  ASSERT_EQ(q.sizes(), torch::IntArrayRef({2, 5}));
  {
    torch::NoGradGuard no_grad;
    EXPECT_TRUE(torch::allclose(q, critic->TargetQ(obs, act)));
  }
  const torch::Tensor old_target = critic->target()->flat().clone();
  critic->online()->flat().add_(1.0f);
  critic->UpdateTarget(0.25);
  EXPECT_TRUE(torch::allclose(critic->target()->flat(), old_target + 0.25f, 1e-6, 1e-6));
}

// ---- squashed Gaussian -----------------------------------------------------

TEST(SquashedGaussianTest, LogProbMatchesChangeOfVariablesDensity) {
  torch::manual_seed(11);
  const int64_t b = 64, a = 3;
  torch::Tensor mean = torch::randn({b, a}) * 1.5;
  torch::Tensor log_std = torch::rand({b, a}) * 2.0 - 1.5;
  SquashedSample s = SampleSquashedGaussian(mean, log_std, at::detail::createCPUGenerator(1));
  ASSERT_EQ(s.action.sizes(), torch::IntArrayRef({b, a}));
  ASSERT_EQ(s.log_prob.sizes(), torch::IntArrayRef({b}));
  // Density of a = tanh(u) in double: p(a) = N(atanh(a)) / (1 - a^2), with
  // the Jacobian also checked by central differences of tanh.
  torch::Tensor act = s.action.to(torch::kFloat64);
  torch::Tensor u = torch::atanh(act);
  torch::Tensor m = mean.to(torch::kFloat64), ls = log_std.to(torch::kFloat64);
  torch::Tensor normal = (-0.5 * ((u - m) / ls.exp()).square() - ls -
                          0.5 * std::log(2 * std::numbers::pi)).sum(-1);
  torch::Tensor exact = normal - torch::log(1 - act.square()).sum(-1);
  const double h = 1e-6;
  torch::Tensor fd = (torch::tanh(u + h) - torch::tanh(u - h)) / (2 * h);
  torch::Tensor numeric = normal - torch::log(fd).sum(-1);
  // Samples where float tanh saturates lose the inverse; skip them.
  torch::Tensor ok = (act.abs() < 0.999).all(-1);
  ASSERT_GT(ok.sum().item<int64_t>(), b / 2);
  torch::Tensor ours = s.log_prob.to(torch::kFloat64);
  EXPECT_TRUE(torch::allclose(ours.masked_select(ok), exact.masked_select(ok), 1e-3, 2e-3));
  EXPECT_TRUE(torch::allclose(ours.masked_select(ok), numeric.masked_select(ok), 1e-3, 2e-3));
}

TEST(SquashedGaussianTest, StableWhereTanhSaturates) {
  // u = 12: 1 - tanh(u)^2 underflows to 0 in float; the stable form does not.
  torch::Tensor u = torch::full({1, 1}, 12.0f);
  const double expected = std::log(4.0) - 2 * 12.0 - 2 * std::log1p(std::exp(-24.0));
  EXPECT_NEAR(TanhLogAbsDetJacobian(u).item<double>(), expected, 1e-4);
  EXPECT_TRUE(std::isinf(torch::log(1 - torch::tanh(u).square()).item<float>()));
  SquashedSample s = SampleSquashedGaussian(torch::full({4, 2}, 30.0f), torch::full({4, 2}, -5.0f));
  EXPECT_TRUE(torch::isfinite(s.log_prob).all().item<bool>());
}

TEST(SquashedGaussianTest, LogProbIntegratesToOne) {
  // 1-D density over (-1, 1) by the midpoint rule.
  const int n = 200000;
  torch::Tensor a = (torch::arange(n, torch::kFloat64) + 0.5) * (2.0 / n) - 1.0;
  torch::Tensor u = torch::atanh(a).unsqueeze(-1);
  torch::Tensor mean = torch::full_like(u, 0.7), log_std = torch::full_like(u, -0.3);
  torch::Tensor logp = DiagGaussianLogProb(u, mean, log_std) - TanhLogAbsDetJacobian(u);
  EXPECT_NEAR((logp.exp().sum() * (2.0 / n)).item<double>(), 1.0, 1e-3);
}

TEST(GaussianPolicyTest, LogStdBoundedAndMeanActionDeterministic) {
  GaussianPolicyOptions o;
  o.obs_dim = 4;
  o.action_dim = 2;
  o.hidden_dim = 8;
  o.num_layers = 1;
  GaussianPolicy policy(o);
  // Huge inputs push the raw log-std to both tanh tails.
  torch::Tensor obs = torch::randn({50, 4}) * 1e4;
  PolicyOutput out = policy->forward(obs);
  EXPECT_GE(out.log_std.min().item<double>(), -20.0);
  EXPECT_LE(out.log_std.max().item<double>(), 2.0);
  EXPECT_TRUE(torch::equal(policy->MeanAction(obs), torch::tanh(out.mean)));
  SquashedSample s = policy->Sample(obs.narrow(0, 0, 5) * 1e-4, c10::nullopt);
  EXPECT_LE(s.action.abs().max().item<float>(), 1.0f);
  EXPECT_TRUE(s.log_prob.requires_grad());
  EXPECT_EQ(BoundLogStd(torch::zeros({1}), -20, 2).item<float>(), -9.0f);
}


// ---- multi-head outputs ----------------------------------------------------

TEST(SelectHeadsTest, PicksEachRowsBlockByHand) {
  // Two rows, three heads of two values: row 0 takes head 2, row 1 head 0.
  torch::Tensor out = torch::arange(12, torch::kFloat32).view({2, 6});
  torch::Tensor picked = SelectHeads(out, torch::tensor({2, 0}, torch::kInt64), 2);
  EXPECT_TRUE(torch::equal(picked, torch::tensor({4.0f, 5.0f, 6.0f, 7.0f}).view({2, 2})));
  // Ensemble outputs (E, B, H * k).
  torch::Tensor ens = torch::arange(12, torch::kFloat32).view({2, 2, 3});
  torch::Tensor q = SelectHeads(ens, torch::tensor({1, 2}, torch::kInt64), 1);
  EXPECT_TRUE(torch::equal(q, torch::tensor({1.0f, 5.0f, 7.0f, 11.0f}).view({2, 2, 1})));
  EXPECT_THROW(SelectHeads(out, torch::tensor({0}, torch::kInt64), 2), Error);
}

TEST(GaussianPolicyTest, MultiHeadOutputEqualsRunningTheChosenHeadAlone) {
  torch::manual_seed(21);
  GaussianPolicyOptions o;
  o.obs_dim = 5;
  o.action_dim = 2;
  o.hidden_dim = 8;
  o.num_layers = 2;
  o.num_heads = 3;
  GaussianPolicy policy(o);
  const std::vector<torch::Tensor>& p = policy->trunk()->detached_params();
  ASSERT_EQ(p.back().size(0), 3 * 4);  // one (mean, raw log-std) block per head
  torch::Tensor obs = torch::randn({6, 5});
  torch::Tensor head = torch::tensor({0, 1, 2, 2, 1, 0}, torch::kInt64);
  PolicyOutput out = policy->forward(obs, head);
  for (int64_t b = 0; b < 6; ++b) {
    const int64_t h = head[b].item<int64_t>();
    // The shared trunk, then only head h's columns of the last layer.
    std::vector<torch::Tensor> alone(p.begin(), p.end());
    alone[4] = p[4].narrow(1, 4 * h, 4);
    alone[5] = p[5].narrow(0, 4 * h, 4);
    torch::Tensor ref = LinearStack(obs.narrow(0, b, 1), alone);
    EXPECT_TRUE(torch::allclose(out.mean[b], ref[0].narrow(0, 0, 2), 1e-5, 1e-6)) << b;
    EXPECT_TRUE(torch::allclose(out.log_std[b], BoundLogStd(ref[0].narrow(0, 2, 2), -20, 2),
                                1e-5, 1e-6))
        << b;
  }
  EXPECT_THROW(policy->forward(obs), Error);  // a multi-head forward needs heads
}

TEST(TwinCriticTest, MultiHeadQEqualsTheChosenHeadOfEachCritic) {
  torch::manual_seed(22);
  TwinCriticOptions o;
  o.obs_dim = 3;
  o.action_dim = 2;
  o.hidden_dim = 8;
  o.num_layers = 1;
  o.num_heads = 4;
  TwinCritic critic(o);
  torch::Tensor obs = torch::randn({5, 3});
  torch::Tensor act = torch::rand({5, 2});
  torch::Tensor head = torch::tensor({3, 0, 1, 3, 2}, torch::kInt64);
  torch::Tensor q = critic->forward(obs, act, head);
  ASSERT_EQ(q.sizes(), torch::IntArrayRef({2, 5}));
  const std::vector<torch::Tensor>& p = critic->online()->detached_params();
  for (int64_t e = 0; e < 2; ++e) {
    for (int64_t b = 0; b < 5; ++b) {
      const int64_t h = head[b].item<int64_t>();
      std::vector<torch::Tensor> alone = {p[0][e], p[1][e], p[2][e].narrow(1, h, 1),
                                          p[3][e].narrow(1, h, 1)};
      torch::Tensor ref = LinearStack(torch::cat({obs, act}, -1).narrow(0, b, 1), alone);
      EXPECT_NEAR(q[e][b].item<float>(), ref.item<float>(), 1e-5) << e << " " << b;
    }
  }
  torch::NoGradGuard no_grad;
  EXPECT_TRUE(torch::allclose(critic->TargetQ(obs, act, head), q));
}

// ---- task encoder and mixture of encoders -----------------------------------

TEST(TaskEncoderTest, EncodesEveryTaskThroughReluAndMlp) {
  TaskEncoderOptions o;
  o.num_tasks = 3;
  o.embedding_dim = 4;
  o.hidden_dim = 6;
  o.num_layers = 2;
  o.output_dim = 5;
  TaskEncoder enc(o, at::detail::createCPUGenerator(3));
  torch::Tensor z = enc->forward();
  ASSERT_EQ(z.sizes(), torch::IntArrayRef({3, 5}));
  const std::vector<torch::Tensor>& p = enc->detached_params();
  std::vector<torch::Tensor> mlp(p.begin() + 1, p.end());
  EXPECT_TRUE(torch::allclose(z, LinearStack(torch::relu(p[0]), mlp), 1e-5, 1e-6));
  // Gradients reach the embedding rows that are used, and only those.
  enc->ZeroGrad();
  z.index_select(0, torch::tensor({0, 2}, torch::kInt64)).sum().backward();
  torch::Tensor g = enc->embedding().grad();
  EXPECT_GT(g[0].abs().sum().item<float>() + g[2].abs().sum().item<float>(), 0.0f);
  EXPECT_EQ(g[1].abs().sum().item<float>(), 0.0f);
  o.num_tasks = 0;
  EXPECT_THROW(TaskEncoder{o}, ConfigError);
}

MixtureEncoderOptions TinyMixture() {
  MixtureEncoderOptions o;
  o.input_dim = 1;
  o.context_dim = 1;
  o.output_dim = 1;
  o.num_layers = 0;  // each expert one linear map
  o.num_experts = 2;
  o.selector_num_layers = 0;
  return o;
}

TEST(MixtureEncoderTest, WeightsAndMixtureMatchAHandComputation) {
  MixtureEncoder moe(TinyMixture());
  {
    torch::NoGradGuard no_grad;
    const std::vector<torch::Tensor>& p = moe->detached_params();
    // experts: w (2, 1, 1), b (2, 1, 1): e1(x) = 2x, e2(x) = -x + 1.
    p[0].copy_(torch::tensor({2.0f, -1.0f}).view({2, 1, 1}));
    p[1].copy_(torch::tensor({0.0f, 1.0f}).view({2, 1, 1}));
    // selector: logits = c [0, log 3].
    p[2].copy_(torch::tensor({0.0f, static_cast<float>(std::log(3.0))}).view({1, 2}));
    p[3].zero_();
  }
  torch::Tensor w = moe->Weights(torch::ones({1, 1}), moe->params());
  EXPECT_NEAR(w[0][0].item<float>(), 0.25f, 1e-6);
  EXPECT_NEAR(w[0][1].item<float>(), 0.75f, 1e-6);
  // x = 2: e1 = 4, e2 = -1, mixture 0.25 * 4 + 0.75 * -1 = 0.25.
  torch::Tensor mix = moe->Mix(torch::full({1, 1}, 2.0f), w, moe->params());
  EXPECT_NEAR(mix.item<float>(), 0.25f, 1e-6);
  // Temperature 2 halves the logits: weights 1 / (1 + sqrt 3), sqrt 3 / (1 + sqrt 3).
  MixtureEncoderOptions hot = TinyMixture();
  hot.temperature = 2.0;
  MixtureEncoder moe2(hot);
  moe2->flat().copy_(moe->flat());
  torch::Tensor w2 = moe2->Weights(torch::ones({1, 1}), moe2->params());
  EXPECT_NEAR(w2[0][0].item<float>(), 1.0 / (1.0 + std::sqrt(3.0)), 1e-6);
}

TEST(MixtureEncoderTest, RandomWeightsSumToOneAndExpertsRunAsOneBatch) {
  MixtureEncoderOptions o;
  o.input_dim = 7;
  o.context_dim = 5;
  o.output_dim = 6;
  o.hidden_dim = 8;
  o.num_experts = 3;
  o.selector_hidden_dim = 4;
  MixtureEncoder moe(o, at::detail::createCPUGenerator(9));
  torch::Tensor w = moe->Weights(torch::randn({10, 5}) * 3, moe->params());
  ASSERT_EQ(w.sizes(), torch::IntArrayRef({10, 3}));
  EXPECT_TRUE(torch::allclose(w.sum(-1), torch::ones({10}), 1e-6, 1e-6));
  EXPECT_GE(w.min().item<float>(), 0.0f);
  torch::Tensor x = torch::randn({10, 7});
  torch::Tensor experts = moe->Experts(x, moe->params());  // (3, 10, 6)
  ASSERT_EQ(experts.sizes(), torch::IntArrayRef({3, 10, 6}));
  torch::Tensor mix = moe->Mix(x, w, moe->params());
  torch::Tensor ref = (w.t().unsqueeze(-1) * experts).sum(0);
  EXPECT_TRUE(torch::allclose(mix, ref, 1e-5, 1e-6));
  // Expert 1 alone equals its slice of the ensemble.
  std::vector<torch::Tensor> one;
  for (size_t i = 0; i < 6; ++i) one.push_back(moe->detached_params()[i][1]);
  EXPECT_TRUE(torch::allclose(experts[1], LinearStack(x, one), 1e-5, 1e-6));
}

// ---- PCGrad ----------------------------------------------------------------

TEST(PcGradTest, NonConflictingGradientsAreAveraged) {
  at::Generator gen = at::detail::createCPUGenerator(0);
  PcGradResult r =
      ProjectConflictingGradients(torch::tensor({1.0f, 0.0f, 0.0f, 1.0f}).view({2, 2}), gen);
  EXPECT_TRUE(torch::allclose(r.gradient, torch::tensor({0.5f, 0.5f})));
  EXPECT_EQ(r.conflicts, 0);
  EXPECT_EQ(r.projections, 0);
  EXPECT_EQ(r.pairs, 2);
}

TEST(PcGradTest, ConflictingPairProjectedByHand) {
  // g1 = (1, 0), g2 = (-1, 1): g1.g2 = -1.
  // g1' = g1 + 1/2 g2 = (0.5, 0.5); g2' = g2 + 1/1 g1 = (0, 1); mean (0.25, 0.75).
  at::Generator gen = at::detail::createCPUGenerator(0);
  PcGradResult r =
      ProjectConflictingGradients(torch::tensor({1.0f, 0.0f, -1.0f, 1.0f}).view({2, 2}), gen);
  EXPECT_NEAR(r.gradient[0].item<float>(), 0.25f, 1e-7);
  EXPECT_NEAR(r.gradient[1].item<float>(), 0.75f, 1e-7);
  EXPECT_EQ(r.conflicts, 2);
  EXPECT_EQ(r.projections, 2);
  // One task: its gradient unchanged.
  PcGradResult one = ProjectConflictingGradients(torch::tensor({{3.0f, -2.0f}}), gen);
  EXPECT_TRUE(torch::equal(one.gradient, torch::tensor({3.0f, -2.0f})));
  EXPECT_THROW(ProjectConflictingGradients(torch::zeros({2}), gen), Error);
}

TEST(PcGradTest, ThreeTasksFollowTheDrawnOrderByHand) {
  // g0 = (1, 0), g1 = (-1, 1), g2 = (-1, -1); g0.g1 = g0.g2 = -1, g1.g2 = 0.
  //  task 0, either order: + 1/2 g1 -> (0.5, 0.5), + 1/2 g2 -> (0, 0) (or the
  //    mirror path): (0, 0).
  //  task 1: g0 first: + g0 -> (0, 1), which now conflicts with g2:
  //    + 1/2 g2 -> (-0.5, 0.5). g2 first: no conflict, then + g0 -> (0, 1).
  //  task 2: g0 first -> (0, -1) -> + 1/2 g1 -> (-0.5, -0.5); g1 first -> (0, -1).
  const torch::Tensor g = torch::tensor({1.0f, 0.0f, -1.0f, 1.0f, -1.0f, -1.0f}).view({3, 2});
  for (uint64_t seed = 0; seed < 8; ++seed) {
    at::Generator gen = at::detail::createCPUGenerator(seed);
    at::Generator replay = gen.clone();
    std::vector<std::vector<int64_t>> orders;
    for (int i = 0; i < 3; ++i) {
      torch::Tensor p = torch::randperm(3, replay, torch::kInt64);
      orders.push_back(std::vector<int64_t>(p.data_ptr<int64_t>(), p.data_ptr<int64_t>() + 3));
    }
    auto before = [](const std::vector<int64_t>& order, int64_t a, int64_t b) {
      for (int64_t j : order) {
        if (j == a) return true;
        if (j == b) return false;
      }
      return false;
    };
    const bool t1_g0_first = before(orders[1], 0, 2);
    const bool t2_g0_first = before(orders[2], 0, 1);
    const float x = (t1_g0_first ? -0.5f : 0.0f) + (t2_g0_first ? -0.5f : 0.0f);
    const float y = (t1_g0_first ? 0.5f : 1.0f) + (t2_g0_first ? -0.5f : -1.0f);
    PcGradResult r = ProjectConflictingGradients(g, gen);
    EXPECT_NEAR(r.gradient[0].item<float>(), x / 3, 1e-6) << seed;
    EXPECT_NEAR(r.gradient[1].item<float>(), y / 3, 1e-6) << seed;
    EXPECT_EQ(r.conflicts, 4);  // (0,1), (1,0), (0,2), (2,0)
    EXPECT_EQ(r.projections, 2 + (t1_g0_first ? 2 : 1) + (t2_g0_first ? 2 : 1)) << seed;
  }
}

TEST(PcGradTest, MatchesDirectProjectionOnRandomGradients) {
  torch::manual_seed(31);
  torch::Tensor g = torch::randn({5, 40});
  at::Generator gen = at::detail::createCPUGenerator(11);
  at::Generator replay = gen.clone();
  PcGradResult r = ProjectConflictingGradients(g, gen);
  torch::Tensor gd = g.to(torch::kFloat64);
  torch::Tensor sum = torch::zeros({40}, torch::kFloat64);
  for (int64_t i = 0; i < 5; ++i) {
    torch::Tensor gi = gd[i].clone();
    torch::Tensor order = torch::randperm(5, replay, torch::kInt64);
    for (int64_t n = 0; n < 5; ++n) {
      const int64_t j = order[n].item<int64_t>();
      const double dot = gi.dot(gd[j]).item<double>();
      if (j != i && dot < 0) gi -= dot / gd[j].dot(gd[j]).item<double>() * gd[j];
    }
    sum += gi;
  }
  EXPECT_TRUE(torch::allclose(r.gradient.to(torch::kFloat64), sum / 5, 1e-5, 1e-6));
  EXPECT_GT(r.conflicts, 0);
}

}  // namespace
}  // namespace manyworlds::nn
