#include "manyworlds/nn/mlp.h"

#include <algorithm>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {
namespace {

void CheckOptions(const MlpOptions& o, const char* what) {
  auto fail = [&](const std::string& msg) {
    throw ConfigError(std::string(what) + ": " + msg);
  };
  if (o.input_dim <= 0) fail("input_dim must be > 0, got " + std::to_string(o.input_dim));
  if (o.output_dim <= 0) fail("output_dim must be > 0, got " + std::to_string(o.output_dim));
  if (o.num_layers < 0) fail("num_layers must be >= 0, got " + std::to_string(o.num_layers));
  if (o.num_layers > 0 && o.hidden_dim <= 0) {
    fail("hidden_dim must be > 0, got " + std::to_string(o.hidden_dim));
  }
  if (o.ensemble_size <= 0) {
    fail("ensemble_size must be > 0, got " + std::to_string(o.ensemble_size));
  }
}

// Widths of the linear maps' inputs and outputs: in, h, ..., h, out.
std::vector<int64_t> Widths(const MlpOptions& o) {
  std::vector<int64_t> widths = {o.input_dim};
  for (int64_t i = 0; i < o.num_layers; ++i) widths.push_back(o.hidden_dim);
  widths.push_back(o.output_dim);
  return widths;
}

// Layout w0, b0, w1, b1, ...; `ensemble` > 0 prefixes every shape with E and
// gives biases a broadcast row: w (E, in, out), b (E, 1, out).
std::vector<ParamSpec> Layout(const MlpOptions& o, int64_t ensemble) {
  const std::vector<int64_t> widths = Widths(o);
  std::vector<ParamSpec> specs;
  for (size_t l = 0; l + 1 < widths.size(); ++l) {
    const std::string suffix = std::to_string(l);
    if (ensemble > 0) {
      specs.push_back({"w" + suffix, {ensemble, widths[l], widths[l + 1]}});
      specs.push_back({"b" + suffix, {ensemble, 1, widths[l + 1]}});
    } else {
      specs.push_back({"w" + suffix, {widths[l], widths[l + 1]}});
      specs.push_back({"b" + suffix, {widths[l + 1]}});
    }
  }
  return specs;
}

void InitWeights(FlatModule& module, c10::optional<at::Generator> generator) {
  const std::vector<torch::Tensor>& views = module.detached_params();
  for (size_t i = 0; i < views.size(); i += 2) {
    InitOrthogonal(views[i], generator);
    views[i + 1].zero_();
  }
}

void CheckParams(at::ArrayRef<torch::Tensor> params, size_t expected) {
  if (params.size() != expected) {
    throw Error("MLP forward expects " + std::to_string(expected) + " parameter tensors, got " +
                std::to_string(params.size()));
  }
}

}  // namespace

void InitOrthogonal(const torch::Tensor& weight, c10::optional<at::Generator> generator) {
  torch::NoGradGuard no_grad;
  if (weight.dim() == 3) {
    for (int64_t e = 0; e < weight.size(0); ++e) InitOrthogonal(weight[e], generator);
    return;
  }
  if (weight.dim() != 2) throw Error("InitOrthogonal expects a matrix or a stack of matrices");
  const int64_t rows = weight.size(0);
  const int64_t cols = weight.size(1);
  // QR of a tall Gaussian matrix; the sign fix makes Q Haar-distributed.
  torch::Tensor a = torch::randn({std::max(rows, cols), std::min(rows, cols)}, generator,
                                 torch::kFloat32);
  auto [q, r] = torch::linalg_qr(a);
  q.mul_(r.diagonal().sign());
  weight.copy_(rows >= cols ? q : q.t());
}

MlpImpl::MlpImpl(const MlpOptions& options, c10::optional<at::Generator> generator)
    : FlatModule("Mlp"), options_(options) {
  CheckOptions(options_, "Mlp");
  options_.ensemble_size = 1;
  InitFlat(Layout(options_, 0));
  InitWeights(*this, generator);
}

torch::Tensor MlpImpl::Forward(const torch::Tensor& x, at::ArrayRef<torch::Tensor> params) const {
  CheckParams(params, 2 * static_cast<size_t>(options_.num_layers + 1));
  torch::Tensor h = x;
  for (size_t i = 0; i < params.size(); i += 2) {
    h = torch::addmm(params[i + 1], h, params[i]);
    // In place is safe: addmm's backward needs its inputs, not its output.
    if (i + 2 < params.size()) h.relu_();
  }
  return h;
}

EnsembleMlpImpl::EnsembleMlpImpl(const MlpOptions& options,
                                 c10::optional<at::Generator> generator)
    : FlatModule("EnsembleMlp"), options_(options) {
  CheckOptions(options_, "EnsembleMlp");
  InitFlat(Layout(options_, options_.ensemble_size));
  InitWeights(*this, generator);
}

torch::Tensor EnsembleMlpImpl::Forward(const torch::Tensor& x,
                                       at::ArrayRef<torch::Tensor> params) const {
  CheckParams(params, 2 * static_cast<size_t>(options_.num_layers + 1));
  const int64_t e = options_.ensemble_size;
  torch::Tensor h = x.dim() == 2 ? x.unsqueeze(0).expand({e, x.size(0), x.size(1)}) : x;
  for (size_t i = 0; i < params.size(); i += 2) {
    h = torch::baddbmm(params[i + 1], h, params[i]);
    if (i + 2 < params.size()) h.relu_();
  }
  return h;
}

}  // namespace manyworlds::nn
