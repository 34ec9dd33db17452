#include "manyworlds/nn/soft_modular.h"

#include <cmath>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {

// Views into the parameter list, in layout order.
struct SoftModularTrunkImpl::Parts {
  torch::Tensor base_w0, base_b0, base_w1, base_b1, embed_w, embed_b;
  std::vector<torch::Tensor> route_w, route_b;  // routing MLP
  std::vector<torch::Tensor> cond_w, cond_b;    // U_l for l = 2..L-1, then U_q
  std::vector<torch::Tensor> logit_w, logit_b;  // W_l for l = 1..L-1, then W_q
  torch::Tensor module0_w, module0_b;           // (E, H, n M): layer 1, modules side by side
  std::vector<torch::Tensor> module_w, module_b;  // (E n, M, M): layers 2..L
  torch::Tensor out_w, out_b;
};

namespace {

// Parameter order of the layout (Cut reads the same order).
std::vector<ParamSpec> Layout(const TaskTrunkOptions& o) {
  const int64_t e = o.ensemble_size, h = o.hidden_dim, g = o.routing_hidden;
  const int64_t n = o.num_modules, m = o.module_hidden, layers = o.module_layers;
  std::vector<ParamSpec> specs;
  auto linear = [&](const std::string& name, int64_t members, int64_t in, int64_t out) {
    specs.push_back({name + "_w", {members, in, out}});
    specs.push_back({name + "_b", {members, 1, out}});
  };
  linear("base0", e, o.input_dim, h);
  linear("base1", e, h, h);
  linear("embed", e, o.num_tasks, h);
  for (int64_t i = 0; i < o.routing_layers; ++i) {
    linear("route" + std::to_string(i), e, i == 0 ? h : g, g);
  }
  linear("logit0", e, g, n * n);
  for (int64_t l = 1; l + 1 < layers; ++l) {
    linear("cond" + std::to_string(l), e, l * n * n, g);
    linear("logit" + std::to_string(l), e, g, n * n);
  }
  linear("condq", e, (layers - 1) * n * n, g);
  linear("logitq", e, g, n);
  linear("module0", e, h, n * m);
  for (int64_t l = 1; l < layers; ++l) linear("module" + std::to_string(l), e * n, m, m);
  linear("out", e, m, o.output_dim);
  return specs;
}

// The authors' fan-in initialiser reads dimension 0 of a PyTorch weight,
// which is the output width: U(+-1/sqrt(out)), biases 0.1.
void InitHidden(const torch::Tensor& w, const torch::Tensor& b,
                c10::optional<at::Generator> generator) {
  InitUniform(w, 1.0 / std::sqrt(static_cast<double>(w.size(-1))), generator);
  b.fill_(0.1);
}

void InitLast(const torch::Tensor& w, const torch::Tensor& b,
              c10::optional<at::Generator> generator) {
  InitUniform(w, 3e-3, generator);
  InitUniform(b, 3e-3, generator);
}

// x (E, B, in) through (E n, in, out) maps, one per module: x_mod (E, B, n, in)
// -> (E, B, n, out).
torch::Tensor ModuleLinear(const torch::Tensor& x, const torch::Tensor& w, const torch::Tensor& b) {
  const int64_t e = x.size(0), bsz = x.size(1), n = x.size(2);
  const torch::Tensor stacked = x.transpose(1, 2).reshape({e * n, bsz, x.size(3)});
  return torch::baddbmm(b, stacked, w).view({e, n, bsz, w.size(2)}).transpose(1, 2);
}

}  // namespace

SoftModularTrunkImpl::SoftModularTrunkImpl(const TaskTrunkOptions& options,
                                           c10::optional<at::Generator> generator)
    : TrunkImpl("SoftModularTrunk"), options_(options) {
  RequirePositive("soft_modular", {{"input_dim", options.input_dim},
                                   {"output_dim", options.output_dim},
                                   {"num_tasks", options.num_tasks},
                                   {"ensemble_size", options.ensemble_size},
                                   {"hidden_dim", options.hidden_dim},
                                   {"num_modules", options.num_modules},
                                   {"module_hidden", options.module_hidden},
                                   {"routing_layers", options.routing_layers},
                                   {"routing_hidden", options.routing_hidden}});
  if (options.module_layers < 2) {
    throw ConfigError("soft_modular: module_layers must be >= 2 (routing mixes between layers), "
                      "got " + std::to_string(options.module_layers));
  }
  InitFlat(Layout(options));
  torch::NoGradGuard no_grad;
  const Parts parts = Cut(detached_params());
  InitHidden(parts.base_w0, parts.base_b0, generator);
  InitHidden(parts.base_w1, parts.base_b1, generator);
  InitHidden(parts.embed_w, parts.embed_b, generator);
  for (size_t i = 0; i < parts.route_w.size(); ++i) {
    InitHidden(parts.route_w[i], parts.route_b[i], generator);
  }
  for (size_t i = 0; i < parts.cond_w.size(); ++i) {
    InitHidden(parts.cond_w[i], parts.cond_b[i], generator);
  }
  for (size_t i = 0; i < parts.logit_w.size(); ++i) {
    InitLast(parts.logit_w[i], parts.logit_b[i], generator);
  }
  InitHidden(parts.module0_w.view({options.ensemble_size, options.hidden_dim,
                                   options.num_modules, options.module_hidden}),
             parts.module0_b, generator);
  for (size_t i = 0; i < parts.module_w.size(); ++i) {
    InitHidden(parts.module_w[i], parts.module_b[i], generator);
  }
  InitLast(parts.out_w, parts.out_b, generator);
}

SoftModularTrunkImpl::Parts SoftModularTrunkImpl::Cut(at::ArrayRef<torch::Tensor> params) const {
  const int64_t layers = options_.module_layers;
  const size_t expected = 2 * static_cast<size_t>(3 + options_.routing_layers + 1 +
                                                  2 * (layers - 2) + 2 + layers + 1);
  if (params.size() != expected) {
    throw Error("SoftModularTrunk: expected " + std::to_string(expected) +
                " parameter tensors, got " + std::to_string(params.size()));
  }
  Parts p;
  size_t i = 0;
  auto next = [&](torch::Tensor& w, torch::Tensor& b) {
    w = params[i++];
    b = params[i++];
  };
  auto push = [&](std::vector<torch::Tensor>& ws, std::vector<torch::Tensor>& bs) {
    ws.push_back(params[i++]);
    bs.push_back(params[i++]);
  };
  next(p.base_w0, p.base_b0);
  next(p.base_w1, p.base_b1);
  next(p.embed_w, p.embed_b);
  for (int64_t r = 0; r < options_.routing_layers; ++r) push(p.route_w, p.route_b);
  push(p.logit_w, p.logit_b);
  for (int64_t l = 1; l + 1 < layers; ++l) {
    push(p.cond_w, p.cond_b);
    push(p.logit_w, p.logit_b);
  }
  push(p.cond_w, p.cond_b);
  push(p.logit_w, p.logit_b);
  next(p.module0_w, p.module0_b);
  for (int64_t l = 1; l < layers; ++l) push(p.module_w, p.module_b);
  next(p.out_w, p.out_b);
  return p;
}

std::vector<torch::Tensor> SoftModularTrunkImpl::Route(const torch::Tensor& base,
                                                       const torch::Tensor& task,
                                                       const Parts& p) const {
  const int64_t e = options_.ensemble_size, b = base.size(1), n = options_.num_modules;
  // Linear(one-hot) is a row of the weight plus the bias.
  const torch::Tensor embedding = (p.embed_w.index_select(1, task) + p.embed_b) * base;
  torch::Tensor z = torch::relu(embedding);
  for (size_t r = 0; r < p.route_w.size(); ++r) {
    z = MemberLinear(z, p.route_w[r], p.route_b[r]);
    if (r + 1 < p.route_w.size()) z = torch::relu(z);
  }
  std::vector<torch::Tensor> probs;
  std::vector<torch::Tensor> flat;
  probs.push_back(
      torch::softmax(MemberLinear(torch::relu(z), p.logit_w[0], p.logit_b[0]).view({e, b, n, n}),
                     -1));
  flat.push_back(probs.back().view({e, b, n * n}));
  for (size_t l = 0; l < p.cond_w.size(); ++l) {
    const torch::Tensor cond =
        torch::relu(MemberLinear(torch::cat(flat, -1), p.cond_w[l], p.cond_b[l]) * z);
    const torch::Tensor logits = MemberLinear(cond, p.logit_w[l + 1], p.logit_b[l + 1]);
    if (l + 1 < p.cond_w.size()) {
      probs.push_back(torch::softmax(logits.view({e, b, n, n}), -1));
      flat.push_back(probs.back().view({e, b, n * n}));
    } else {
      probs.push_back(torch::softmax(logits, -1));  // output weights (E, B, n)
    }
  }
  return probs;
}

std::vector<torch::Tensor> SoftModularTrunkImpl::Routing(const torch::Tensor& x,
                                                         const torch::Tensor& task) const {
  torch::NoGradGuard no_grad;
  const Parts p = Cut(detached_params());
  const torch::Tensor in = ForMembers(x, options_.ensemble_size);
  const torch::Tensor base =
      MemberLinear(torch::relu(MemberLinear(in, p.base_w0, p.base_b0)), p.base_w1, p.base_b1);
  return Route(base, task, p);
}

torch::Tensor SoftModularTrunkImpl::Forward(const torch::Tensor& x, const torch::Tensor& task,
                                            at::ArrayRef<torch::Tensor> params) const {
  CheckTrunkTask("SoftModularTrunk", task, x.size(-2));
  const Parts p = Cut(params);
  const int64_t e = options_.ensemble_size, b = x.size(-2), n = options_.num_modules;
  const torch::Tensor in = ForMembers(x, e);
  const torch::Tensor base =
      MemberLinear(torch::relu(MemberLinear(in, p.base_w0, p.base_b0)), p.base_w1, p.base_b1);
  const std::vector<torch::Tensor> probs = Route(base, task, p);
  torch::Tensor modules = MemberLinear(torch::relu(base), p.module0_w, p.module0_b)
                              .view({e, b, n, options_.module_hidden});
  for (size_t l = 0; l < p.module_w.size(); ++l) {
    modules = ModuleLinear(torch::relu(torch::matmul(probs[l], modules)), p.module_w[l],
                           p.module_b[l]);
  }
  const torch::Tensor mixed =
      torch::relu(torch::matmul(probs.back().unsqueeze(2), modules).squeeze(2));
  return MemberOutput(MemberLinear(mixed, p.out_w, p.out_b), e);
}

}  // namespace manyworlds::nn
