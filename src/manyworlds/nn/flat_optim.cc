#include "manyworlds/nn/flat_optim.h"

#include <cmath>
#include <string>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {
namespace {

void CheckFlat(const torch::Tensor& t, int64_t size, const char* what) {
  if (t.defined() && t.device().is_cpu() && t.scalar_type() == torch::kFloat32 &&
      t.is_contiguous() && t.numel() == size) {
    return;
  }
  throw Error(std::string(what) + ": expected a contiguous CPU float32 tensor of " +
              std::to_string(size) + " elements");
}

}  // namespace

FlatAdam::FlatAdam(int64_t size, const AdamOptions& options) : options_(options) {
  const AdamOptions& o = options_;
  if (size < 0) throw ConfigError("FlatAdam: size must be >= 0, got " + std::to_string(size));
  if (!(o.lr >= 0.0)) throw ConfigError("FlatAdam: lr must be >= 0");
  if (!(o.beta1 >= 0.0 && o.beta1 < 1.0) || !(o.beta2 >= 0.0 && o.beta2 < 1.0)) {
    throw ConfigError("FlatAdam: beta1 and beta2 must lie in [0, 1)");
  }
  if (!(o.eps > 0.0)) throw ConfigError("FlatAdam: eps must be > 0");
  if (!(o.weight_decay >= 0.0)) throw ConfigError("FlatAdam: weight_decay must be >= 0");
  exp_avg_ = torch::zeros({size}, torch::kFloat32);
  exp_avg_sq_ = torch::zeros({size}, torch::kFloat32);
}

void FlatAdam::Step(const torch::Tensor& param, const torch::Tensor& grad) {
  const int64_t n = size();
  CheckFlat(param, n, "FlatAdam::Step param");
  CheckFlat(grad, n, "FlatAdam::Step grad");
  ++step_;
  // Scalars in double, like torch::optim::Adam, then rounded once to float.
  const double t = static_cast<double>(step_);
  const double bias_correction1 = 1.0 - std::pow(options_.beta1, t);
  const double bias_correction2 = 1.0 - std::pow(options_.beta2, t);
  const float b1 = static_cast<float>(options_.beta1);
  const float b2 = static_cast<float>(options_.beta2);
  const float one_minus_b1 = static_cast<float>(1.0 - options_.beta1);
  const float one_minus_b2 = static_cast<float>(1.0 - options_.beta2);
  const float inv_sqrt_bc2 = static_cast<float>(1.0 / std::sqrt(bias_correction2));
  const float eps = static_cast<float>(options_.eps);
  const float step_size = static_cast<float>(options_.lr / bias_correction1);
  const float wd = static_cast<float>(options_.weight_decay);

  float* __restrict__ p = param.data_ptr<float>();
  const float* __restrict__ g = grad.data_ptr<float>();
  float* __restrict__ m = exp_avg_.data_ptr<float>();
  float* __restrict__ v = exp_avg_sq_.data_ptr<float>();
  for (int64_t i = 0; i < n; ++i) {
    const float gi = g[i] + wd * p[i];
    const float mi = b1 * m[i] + one_minus_b1 * gi;
    const float vi = b2 * v[i] + one_minus_b2 * gi * gi;
    m[i] = mi;
    v[i] = vi;
    p[i] -= step_size * (mi / (std::sqrt(vi) * inv_sqrt_bc2 + eps));
  }
}

void FlatAdam::Save(torch::serialize::OutputArchive& archive) const {
  archive.write("step", torch::tensor(step_, torch::kInt64));
  archive.write("exp_avg", exp_avg_);
  archive.write("exp_avg_sq", exp_avg_sq_);
}

void FlatAdam::Load(torch::serialize::InputArchive& archive) {
  torch::Tensor step, m, v;
  archive.read("step", step);
  archive.read("exp_avg", m);
  archive.read("exp_avg_sq", v);
  if (m.numel() != size() || v.numel() != size() || step.numel() != 1) {
    throw Error("FlatAdam::Load: state of " + std::to_string(m.numel()) +
                " parameters, this optimizer has " + std::to_string(size()));
  }
  step_ = step.item<int64_t>();
  exp_avg_.copy_(m.reshape({-1}));
  exp_avg_sq_.copy_(v.reshape({-1}));
}

void PolyakUpdate(const torch::Tensor& target, const torch::Tensor& source, double tau) {
  if (!(tau >= 0.0 && tau <= 1.0)) {
    throw Error("PolyakUpdate: tau must lie in [0, 1], got " + std::to_string(tau));
  }
  const int64_t n = target.numel();
  CheckFlat(target, n, "PolyakUpdate target");
  CheckFlat(source, n, "PolyakUpdate source");
  const float a = static_cast<float>(1.0 - tau);
  const float b = static_cast<float>(tau);
  float* __restrict__ t = target.data_ptr<float>();
  const float* __restrict__ s = source.data_ptr<float>();
  for (int64_t i = 0; i < n; ++i) t[i] = a * t[i] + b * s[i];
}

}  // namespace manyworlds::nn
