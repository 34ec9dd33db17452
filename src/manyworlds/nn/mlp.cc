#include "manyworlds/nn/mlp.h"

#include <algorithm>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/tanh.h"

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

size_t AppendMlpLayout(std::vector<ParamSpec>& specs, const std::string& prefix,
                       const MlpOptions& options, bool ensemble) {
  CheckOptions(options, "Mlp");
  // Layout w0, b0, w1, b1, ...; an ensemble prefixes every shape with E and
  // gives biases a broadcast row: w (E, in, out), b (E, 1, out).
  const std::vector<int64_t> widths = Widths(options);
  const int64_t e = options.ensemble_size;
  for (size_t l = 0; l + 1 < widths.size(); ++l) {
    const std::string suffix = std::to_string(l);
    if (ensemble) {
      specs.push_back({prefix + "w" + suffix, {e, widths[l], widths[l + 1]}});
      specs.push_back({prefix + "b" + suffix, {e, 1, widths[l + 1]}});
    } else {
      specs.push_back({prefix + "w" + suffix, {widths[l], widths[l + 1]}});
      specs.push_back({prefix + "b" + suffix, {widths[l + 1]}});
    }
  }
  return 2 * (widths.size() - 1);
}

void InitMlpParams(at::ArrayRef<torch::Tensor> params, c10::optional<at::Generator> generator) {
  torch::NoGradGuard no_grad;
  for (size_t i = 0; i + 1 < params.size(); i += 2) {
    InitOrthogonal(params[i], generator);
    params[i + 1].zero_();
  }
}

torch::Tensor MlpForward(const torch::Tensor& x, at::ArrayRef<torch::Tensor> params,
                         Activation activation) {
  if (params.empty() || params.size() % 2 != 0) {
    throw Error("MlpForward: expects (w, b) pairs, got " + std::to_string(params.size()) +
                " tensors");
  }
  const bool ensemble = params[0].dim() == 3;
  if (ensemble && x.size(-2) >= kEnsembleSplitRows) {
    // One addmm chain per member: at this many rows it beats baddbmm (see
    // kEnsembleSplitRows). Equal to the baddbmm path up to rounding.
    const int64_t members = params[0].size(0);
    std::vector<torch::Tensor> member_params(params.size());
    std::vector<torch::Tensor> outputs;
    outputs.reserve(static_cast<size_t>(members));
    for (int64_t e = 0; e < members; ++e) {
      for (size_t i = 0; i < params.size(); ++i) {
        member_params[i] = params[i][e];
      }
      outputs.push_back(MlpForward(x.dim() == 3 ? x[e] : x, member_params, activation));
    }
    return torch::stack(outputs);
  }
  torch::Tensor h = x;
  if (ensemble && h.dim() == 2) {
    h = h.unsqueeze(0).expand({params[0].size(0), h.size(0), h.size(1)});
  }
  for (size_t i = 0; i < params.size(); i += 2) {
    h = ensemble ? torch::baddbmm(params[i + 1], h, params[i])
                 : torch::addmm(params[i + 1], h, params[i]);
    // In place is safe: addmm's backward needs its inputs, not its output.
    if (i + 2 < params.size()) {
      if (activation == Activation::kRelu) {
        h.relu_();
      } else {
        h = Tanh(h);  // tanh's backward needs its output: not in place
      }
    }
  }
  return h;
}

torch::Tensor SelectHeads(const torch::Tensor& out, const torch::Tensor& head, int64_t head_dim) {
  const int64_t d = out.dim();
  if ((d != 2 && d != 3) || out.size(-1) % head_dim != 0 || head.dim() != 1 ||
      head.size(0) != out.size(-2)) {
    throw Error("SelectHeads: expected out (B, H * k) or (E, B, H * k) and head (B)");
  }
  const int64_t heads = out.size(-1) / head_dim;
  const int64_t b = out.size(-2);
  if (d == 2) {
    torch::Tensor index = head.view({b, 1, 1}).expand({b, 1, head_dim});
    return out.view({b, heads, head_dim}).gather(1, index).squeeze(1);
  }
  const int64_t e = out.size(0);
  torch::Tensor index = head.view({1, b, 1, 1}).expand({e, b, 1, head_dim});
  return out.view({e, b, heads, head_dim}).gather(2, index).squeeze(2);
}

template <bool kEnsemble>
BasicMlpImpl<kEnsemble>::BasicMlpImpl(const MlpOptions& options,
                                      c10::optional<at::Generator> generator)
    : TrunkImpl(kEnsemble ? "EnsembleMlp" : "Mlp"), options_(options) {
  CheckOptions(options_, kEnsemble ? "EnsembleMlp" : "Mlp");
  if (!kEnsemble) options_.ensemble_size = 1;
  std::vector<ParamSpec> specs;
  AppendMlpLayout(specs, "", options_, kEnsemble);
  InitFlat(std::move(specs));
  InitMlpParams(detached_params(), generator);
}

template <bool kEnsemble>
torch::Tensor BasicMlpImpl<kEnsemble>::Forward(const torch::Tensor& x,
                                               at::ArrayRef<torch::Tensor> params) const {
  CheckParams(params, 2 * static_cast<size_t>(options_.num_layers + 1));
  return MlpForward(x, params, options_.activation);
}

template class BasicMlpImpl<false>;
template class BasicMlpImpl<true>;

}  // namespace manyworlds::nn
