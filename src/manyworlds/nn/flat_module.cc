#include "manyworlds/nn/flat_module.h"

#include <utility>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {
namespace {

// Zeroes the flat gradient and points each parameter's .grad at its view of
// it, re-attaching views that something (e.g. Module::zero_grad(true))
// replaced or cleared. Backward then accumulates in place into flat_grad.
void ZeroAndAttachGrads(const torch::Tensor& flat_grad, std::vector<torch::Tensor>& params,
                        const std::vector<torch::Tensor>& grad_views) {
  flat_grad.zero_();
  for (size_t i = 0; i < params.size(); ++i) {
    torch::Tensor& grad = params[i].mutable_grad();
    if (!grad.defined() || !grad.is_same(grad_views[i])) grad = grad_views[i];
  }
}

}  // namespace

void FlatModule::InitFlat(std::vector<ParamSpec> specs) {
  if (flat_.defined()) throw Error("FlatModule::InitFlat called twice on " + name());
  specs_ = std::move(specs);
  int64_t total = 0;
  for (const ParamSpec& spec : specs_) {
    int64_t n = 1;
    for (int64_t d : spec.shape) n *= d;
    total += n;
  }
  flat_ = torch::zeros({total}, torch::kFloat32);
  flat_grad_ = torch::zeros({total}, torch::kFloat32);
  int64_t offset = 0;
  for (const ParamSpec& spec : specs_) {
    int64_t n = 1;
    for (int64_t d : spec.shape) n *= d;
    torch::Tensor values = flat_.narrow(0, offset, n).view(spec.shape);
    grad_views_.push_back(flat_grad_.narrow(0, offset, n).view(spec.shape));
    // flat_ itself does not require grad, so each view is a leaf of its own.
    torch::Tensor param = register_parameter(spec.name, values.detach(), true);
    params_.push_back(param);
    detached_params_.push_back(values);
    offset += n;
  }
  ZeroGrad();
}

void FlatModule::ZeroGrad() { ZeroAndAttachGrads(flat_grad_, params_, grad_views_); }

void GradientReplica::ZeroGrad() { ZeroAndAttachGrads(flat_grad, params, grad_views_); }

GradientReplica FlatModule::MakeGradientReplica() const {
  GradientReplica replica;
  replica.flat_grad = torch::zeros({num_params()}, torch::kFloat32);
  int64_t offset = 0;
  for (const ParamSpec& spec : specs_) {
    const int64_t n = detached_params_[replica.params.size()].numel();
    replica.params.push_back(
        flat_.narrow(0, offset, n).view(spec.shape).detach().requires_grad_(true));
    replica.grad_views_.push_back(replica.flat_grad.narrow(0, offset, n).view(spec.shape));
    offset += n;
  }
  replica.ZeroGrad();
  return replica;
}

void FlatModule::CopyFrom(const FlatModule& other) {
  bool same = specs_.size() == other.specs_.size();
  for (size_t i = 0; same && i < specs_.size(); ++i) {
    same = specs_[i].shape == other.specs_[i].shape;
  }
  if (!same) {
    throw Error("FlatModule::CopyFrom: layouts differ (" + name() + " <- " + other.name() + ")");
  }
  torch::NoGradGuard no_grad;
  flat_.copy_(other.flat_);
}

void FlatModule::save(torch::serialize::OutputArchive& archive) const {
  archive.write("flat", flat_);
}

void FlatModule::load(torch::serialize::InputArchive& archive) {
  torch::Tensor loaded;
  archive.read("flat", loaded);
  if (loaded.numel() != flat_.numel() || loaded.scalar_type() != torch::kFloat32) {
    throw Error("FlatModule::load: " + name() + " expects " + std::to_string(flat_.numel()) +
                " float32 values, the archive holds " + std::to_string(loaded.numel()));
  }
  // Copy, never rebind: the parameter views must keep pointing into flat_.
  torch::NoGradGuard no_grad;
  flat_.copy_(loaded);
}

}  // namespace manyworlds::nn
