// The task-dependent networks (Soft Modularization, PaCo, MOORE): each
// vectorised forward against a plain, one-row-at-a-time reading of the
// authors' structure, ensembles against their members, and the registry.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/mlp.h"
#include "manyworlds/nn/moore.h"
#include "manyworlds/nn/paco.h"
#include "manyworlds/nn/soft_modular.h"
#include "manyworlds/nn/task_trunks.h"

namespace manyworlds::nn {
namespace {

TaskTrunkOptions Small(int64_t members) {
  TaskTrunkOptions o;
  o.input_dim = 5;
  o.output_dim = 3;
  o.num_tasks = 4;
  o.ensemble_size = members;
  o.hidden_dim = 7;
  o.num_layers = 2;
  o.num_experts = 3;
  o.num_param_sets = 3;
  o.num_modules = 3;
  o.module_layers = 3;  // exercises the middle routing step
  o.module_hidden = 6;
  o.routing_layers = 2;
  o.routing_hidden = 8;
  return o;
}

const torch::Tensor kTask = torch::tensor({0, 3, 1, 1, 2, 0}, torch::kInt64);

torch::Tensor Input(uint64_t seed) {
  at::Generator g = at::detail::createCPUGenerator(seed);
  return torch::randn({6, 5}, g, torch::kFloat32);
}

// Member e of every parameter of an ensemble layout (leading dim E, or E*n
// for module stacks), for comparing an ensemble with one-member trunks.
std::vector<torch::Tensor> Member(const TrunkImpl& trunk, int64_t members, int64_t e) {
  std::vector<torch::Tensor> out;
  for (const torch::Tensor& p : trunk.detached_params()) {
    const int64_t per = p.size(0) / members;
    out.push_back(p.narrow(0, e * per, per));
  }
  return out;
}

// Every parameter redrawn from N(0, 0.5^2).
void Redraw(TrunkImpl& trunk, uint64_t seed) {
  torch::NoGradGuard no_grad;
  at::Generator g = at::detail::createCPUGenerator(seed);
  for (torch::Tensor p : trunk.detached_params()) p.normal_(0.0, 0.5, g);
}

TEST(GramSchmidtTest, GivesAnOrthonormalBasisOfTheSameSpanInOrder) {
  at::Generator g = at::detail::createCPUGenerator(3);
  const torch::Tensor x = torch::randn({5, 4, 9}, g, torch::kFloat64);
  const torch::Tensor q = GramSchmidt(x);
  const torch::Tensor gram = torch::matmul(q, q.transpose(-1, -2));
  EXPECT_TRUE(torch::allclose(gram, torch::eye(4, torch::kFloat64).expand({5, 4, 4}), 1e-10,
                              1e-10));
  // Row i lies in the span of x_0..x_i (triangular change of basis), and the
  // first row is x_0 normalised.
  for (int64_t i = 0; i < 4; ++i) {
    const torch::Tensor span = x.narrow(1, 0, i + 1);  // (5, i + 1, 9)
    const torch::Tensor coef =
        std::get<0>(torch::linalg_lstsq(span.transpose(1, 2), q.select(1, i).unsqueeze(-1)));
    const torch::Tensor back = torch::matmul(span.transpose(1, 2), coef).squeeze(-1);
    EXPECT_TRUE(torch::allclose(back, q.select(1, i), 1e-8, 1e-8)) << i;
  }
  EXPECT_TRUE(torch::allclose(q.select(1, 0),
                              x.select(1, 0) / x.select(1, 0).norm(2, {-1}, true), 1e-12, 1e-12));
}

TEST(MooreTrunkTest, EqualsExpertsOrthogonalisedMixedAndTheTasksHead) {
  const TaskTrunkOptions o = Small(1);
  MooreTrunkImpl moore(o, at::detail::createCPUGenerator(1));
  const std::vector<torch::Tensor>& p = moore.detached_params();
  const torch::Tensor x = Input(2);
  const torch::Tensor out = moore.Forward(x, kTask, p);
  ASSERT_EQ(out.sizes(), (std::vector<int64_t>{6, 3}));
  const size_t experts = p.size() - 3;
  const torch::Tensor task_weights = p[experts][0];  // (T, k)
  for (int64_t row = 0; row < 6; ++row) {
    const int64_t t = kTask[row].item<int64_t>();
    std::vector<torch::Tensor> outs;
    for (int64_t j = 0; j < o.num_experts; ++j) {
      std::vector<torch::Tensor> expert;
      for (size_t i = 0; i < experts; ++i) expert.push_back(p[i][j].squeeze(0));
      outs.push_back(MlpForward(x[row].unsqueeze(0), expert).squeeze(0));
    }
    // Classical Gram-Schmidt, one vector at a time.
    std::vector<torch::Tensor> basis;
    for (torch::Tensor v : outs) {
      for (const torch::Tensor& u : basis) v = v - v.dot(u) * u;
      basis.push_back(v / v.norm());
    }
    torch::Tensor mixed = torch::zeros({o.hidden_dim});
    for (int64_t j = 0; j < o.num_experts; ++j) mixed += task_weights[t][j] * basis[j];
    const torch::Tensor head_w = p[experts + 1][0].narrow(1, t * 3, 3);
    const torch::Tensor head_b = p[experts + 2][0][0].narrow(0, t * 3, 3);
    const torch::Tensor expected = torch::matmul(torch::tanh(mixed), head_w) + head_b;
    EXPECT_TRUE(torch::allclose(out[row], expected, 1e-5, 1e-5)) << row;
  }
}

// Both computations: rows of unequal task counts (K products combined per
// row) and balanced rows (each task's parameters composed first).
class PacoPaths : public ::testing::TestWithParam<bool> {};

TEST_P(PacoPaths, EqualsAnMlpWithTheTasksCombinedParameters) {
  const bool balanced = GetParam();
  const torch::Tensor tasks = balanced ? torch::tensor({3, 1, 0, 2, 1, 0, 2, 3}, torch::kInt64)
                                       : torch::tensor({0, 3, 1, 1, 2, 0, 0, 2}, torch::kInt64);
  const TaskTrunkOptions o = Small(1);
  PacoTrunkImpl paco(o, at::detail::createCPUGenerator(1));
  {
    // The sets start identical; make them differ so the test can fail.
    torch::NoGradGuard no_grad;
    for (torch::Tensor p : paco.detached_params()) {
      p.add_(0.1 * torch::randn(p.sizes(), at::detail::createCPUGenerator(5), torch::kFloat32));
    }
  }
  const std::vector<torch::Tensor>& p = paco.detached_params();
  const torch::Tensor x = torch::randn({8, 5}, at::detail::createCPUGenerator(3));
  const torch::Tensor out = paco.Forward(x, tasks, p);
  const int64_t k = o.num_param_sets;
  for (int64_t row = 0; row < 8; ++row) {
    const torch::Tensor w = paco.task_weights()[0][tasks[row].item<int64_t>()];  // (K)
    std::vector<torch::Tensor> combined;
    for (size_t i = 0; i + 1 < p.size(); ++i) {
      const torch::Tensor sets = p[i][0];  // (in or 1, K * out)
      const int64_t cols = sets.size(1) / k;
      torch::Tensor sum = torch::zeros({sets.size(0), cols});
      for (int64_t j = 0; j < k; ++j) sum += w[j] * sets.narrow(1, j * cols, cols);
      combined.push_back(i % 2 == 0 ? sum : sum.squeeze(0));
    }
    const torch::Tensor expected = MlpForward(x[row].unsqueeze(0), combined).squeeze(0);
    EXPECT_TRUE(torch::allclose(out[row], expected, 1e-5, 1e-5)) << row;
  }
  // The twin-critic ensemble takes the same path and agrees with its members.
  const auto pair = std::make_shared<PacoTrunkImpl>(Small(2), at::detail::createCPUGenerator(4));
  Redraw(*pair, 6);
  const torch::Tensor both = pair->Forward(x, tasks, pair->detached_params());
  PacoTrunkImpl one(o, at::detail::createCPUGenerator(5));
  for (int64_t e = 0; e < 2; ++e) {
    EXPECT_TRUE(torch::allclose(both[e], one.Forward(x, tasks, Member(*pair, 2, e)), 1e-5, 1e-5));
  }
}

INSTANTIATE_TEST_SUITE_P(UnequalAndBalancedRows, PacoPaths, ::testing::Bool());

TEST(PacoTrunkTest, SetsStartIdenticalAndTasksDiffer) {
  const TaskTrunkOptions o = Small(2);
  PacoTrunkImpl paco(o, at::detail::createCPUGenerator(1));
  const torch::Tensor w0 = paco.detached_params()[0];  // (E, in, K * hidden)
  const int64_t h = o.hidden_dim;
  for (int64_t j = 1; j < o.num_param_sets; ++j) {
    EXPECT_TRUE(torch::equal(w0.narrow(2, 0, h), w0.narrow(2, j * h, h))) << j;
  }
  const torch::Tensor out = paco.Forward(torch::ones({2, 5}), torch::tensor({0, 1}), 
                                         paco.detached_params());
  EXPECT_FALSE(torch::allclose(out.select(1, 0), out.select(1, 1)));
}

// One row through the authors' structure, module by module.
torch::Tensor SoftModularRow(const SoftModularTrunkImpl& sm, const TaskTrunkOptions& o,
                             const torch::Tensor& x, int64_t task) {
  const std::vector<torch::Tensor>& p = sm.detached_params();
  size_t i = 0;
  auto lin = [&](const torch::Tensor& v) {
    const torch::Tensor w = p[i][0], b = p[i + 1][0][0];
    i += 2;
    return torch::matmul(v, w) + b;
  };
  const torch::Tensor base = lin(torch::relu(lin(x)));
  const torch::Tensor embed_w = p[i][0], embed_b = p[i + 1][0][0];
  i += 2;
  torch::Tensor z = torch::relu((embed_w[task] + embed_b) * base);
  for (int64_t r = 0; r < o.routing_layers; ++r) {
    z = lin(z);
    if (r + 1 < o.routing_layers) z = torch::relu(z);
  }
  const int64_t n = o.num_modules;
  std::vector<torch::Tensor> probs = {torch::softmax(lin(torch::relu(z)).view({n, n}), -1)};
  for (int64_t l = 1; l + 1 < o.module_layers; ++l) {
    std::vector<torch::Tensor> flat;
    for (const torch::Tensor& q : probs) flat.push_back(q.reshape({-1}));
    const torch::Tensor cond = torch::relu(lin(torch::cat(flat)) * z);
    probs.push_back(torch::softmax(lin(cond).view({n, n}), -1));
  }
  std::vector<torch::Tensor> flat;
  for (const torch::Tensor& q : probs) flat.push_back(q.reshape({-1}));
  const torch::Tensor last = torch::softmax(lin(torch::relu(lin(torch::cat(flat)) * z)), -1);
  // Layer 1: module j reads relu(base).
  const torch::Tensor w0 = p[i][0], b0 = p[i + 1][0][0];
  i += 2;
  std::vector<torch::Tensor> outs;
  for (int64_t j = 0; j < n; ++j) {
    const int64_t m = o.module_hidden;
    outs.push_back(torch::matmul(torch::relu(base), w0.narrow(1, j * m, m)) +
                   b0.narrow(0, j * m, m));
  }
  for (int64_t l = 0; l + 1 < o.module_layers; ++l) {
    const torch::Tensor w = p[i], b = p[i + 1];  // (n, M, M), (n, 1, M)
    i += 2;
    std::vector<torch::Tensor> next;
    for (int64_t j = 0; j < n; ++j) {
      torch::Tensor in = torch::zeros_like(outs[0]);
      for (int64_t k = 0; k < n; ++k) in += probs[l][j][k] * outs[k];
      next.push_back(torch::matmul(torch::relu(in), w[j]) + b[j][0]);
    }
    outs = next;
  }
  torch::Tensor mixed = torch::zeros_like(outs[0]);
  for (int64_t k = 0; k < n; ++k) mixed += last[k] * outs[k];
  return lin(torch::relu(mixed));
}

TEST(SoftModularTrunkTest, EqualsTheModuleByModuleComputation) {
  const TaskTrunkOptions o = Small(1);
  SoftModularTrunkImpl sm(o, at::detail::createCPUGenerator(1));
  // The authors' initialisation makes routing near-uniform and outputs tiny,
  // which would hide a wrong mixing order: draw everything at unit scale.
  Redraw(sm, 8);
  const torch::Tensor x = Input(4);
  const torch::Tensor out = sm.Forward(x, kTask, sm.detached_params());
  for (int64_t row = 0; row < 6; ++row) {
    const torch::Tensor expected = SoftModularRow(sm, o, x[row], kTask[row].item<int64_t>());
    EXPECT_TRUE(torch::allclose(out[row], expected, 1e-5, 1e-6)) << row;
  }
}

TEST(SoftModularTrunkTest, RoutingIsAProbabilityOverTheNextModulesThatDependsOnTheTask) {
  const TaskTrunkOptions o = Small(1);
  SoftModularTrunkImpl sm(o, at::detail::createCPUGenerator(1));
  const torch::Tensor x = Input(5);
  const std::vector<torch::Tensor> probs = sm.Routing(x, kTask);
  ASSERT_EQ(probs.size(), static_cast<size_t>(o.module_layers));
  for (const torch::Tensor& p : probs) {
    EXPECT_TRUE(torch::allclose(p.sum(-1), torch::ones_like(p.sum(-1)), 1e-6, 1e-6));
  }
  // Rows 2 and 3 have the same task; give row 3 row 2's input and another
  // task: the routing changes.
  const torch::Tensor same = x.narrow(0, 2, 1).expand({2, 5});
  const std::vector<torch::Tensor> two = sm.Routing(same, torch::tensor({1, 2}));
  EXPECT_FALSE(torch::allclose(two[0][0][0], two[0][0][1], 1e-7, 1e-7));
}

TEST(TaskTrunkTest, AnEnsembleEqualsItsMembersRunAlone) {
  for (const TaskTrunkInfo& info : TaskTrunks()) {
    const std::shared_ptr<TrunkImpl> pair = info.make(Small(2), at::detail::createCPUGenerator(1));
    const std::shared_ptr<TrunkImpl> one = info.make(Small(1), at::detail::createCPUGenerator(2));
    Redraw(*pair, 9);  // unit-scale values, so that a wrong member would show
    const torch::Tensor x = Input(6);
    const torch::Tensor both = pair->Forward(x, kTask, pair->detached_params());
    ASSERT_EQ(both.sizes(), (std::vector<int64_t>{2, 6, 3})) << info.name;
    for (int64_t e = 0; e < 2; ++e) {
      const torch::Tensor alone = one->Forward(x, kTask, Member(*pair, 2, e));
      EXPECT_TRUE(torch::allclose(both[e], alone, 1e-5, 1e-6)) << info.name << " member " << e;
    }
    EXPECT_FALSE(torch::allclose(both[0], both[1])) << info.name;
  }
}

TEST(TaskTrunkTest, GradientsReachEveryParameterAndTheTaskIsRequired) {
  for (const TaskTrunkInfo& info : TaskTrunks()) {
    const std::shared_ptr<TrunkImpl> trunk =
        info.make(Small(2), at::detail::createCPUGenerator(1));
    EXPECT_TRUE(trunk->uses_task());
    trunk->ZeroGrad();
    // Every task present, so every task's weights get a gradient.
    trunk->Forward(Input(7), torch::tensor({0, 1, 2, 3, 0, 1}), trunk->params()).square().sum()
        .backward();
    for (size_t i = 0; i < trunk->params().size(); ++i) {
      EXPECT_GT(trunk->params()[i].grad().abs().sum().item<float>(), 0.0f)
          << info.name << " " << trunk->specs()[i].name;
    }
    EXPECT_THROW(trunk->Forward(Input(7), torch::Tensor(), trunk->params()), Error) << info.name;
    EXPECT_THROW(trunk->Forward(Input(7), torch::tensor({0, 1}), trunk->params()), Error)
        << info.name;
  }
}

TEST(TaskTrunkTest, RegistryNamesAndBadOptions) {
  std::vector<std::string> names;
  for (const TaskTrunkInfo& info : TaskTrunks()) names.push_back(info.name);
  EXPECT_EQ(names, (std::vector<std::string>{"soft_modular", "paco", "moore"}));
  EXPECT_EQ(LookupTaskTrunk("care"), nullptr);
  EXPECT_THROW(TaskTrunkFactory("care", Small(1)), ConfigError);
  TaskTrunkOptions bad = Small(1);
  bad.module_layers = 1;
  EXPECT_THROW(TaskTrunkFactory("soft_modular", bad)(c10::nullopt), ConfigError);
  bad = Small(1);
  bad.num_experts = 0;
  try {
    TaskTrunkFactory("moore", bad)(c10::nullopt);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("num_experts must be > 0"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace manyworlds::nn
