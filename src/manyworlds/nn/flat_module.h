// A torch::nn::Module whose parameters all live in ONE contiguous buffer.
//
// Every registered parameter is a view into `flat()`, and its gradient is a
// view into `flat_grad()`: backward accumulates in place into the flat
// gradient, so an optimizer or a Polyak update is one loop over one buffer
// instead of a dispatch per tensor (libtorch's per-op dispatch, not the
// arithmetic, dominates updates of networks this small).
//
//   net->ZeroGrad();          // zero the flat gradient (not set_to_none)
//   loss.backward();          // fills flat_grad()
//   adam.Step(net->flat(), net->flat_grad());
//
// CPU, float32 only. Do not move the module to another device or dtype, and
// do not replace parameters: that would break the sharing. Module::save /
// load are overridden to write the flat buffer and copy into it on load.
#ifndef MANYWORLDS_NN_FLAT_MODULE_H_
#define MANYWORLDS_NN_FLAT_MODULE_H_

#include <cstdint>
#include <string>
#include <vector>

#include <torch/torch.h>

namespace manyworlds::nn {

// A second set of leaf tensors over a FlatModule's values whose gradients
// accumulate into a buffer of their own: several threads can then
// backpropagate through the same module at once (one replica each), and the
// caller sums the buffers. Make it after the module is final; it views the
// module's storage and must not outlive it.
struct GradientReplica {
  std::vector<torch::Tensor> params;  // layout order, require grad
  torch::Tensor flat_grad;            // (num_params) float32
  // Zeroes flat_grad and re-attaches the gradient views (as ZeroGrad).
  void ZeroGrad();
 private:
  friend class FlatModule;
  std::vector<torch::Tensor> grad_views_;
};

// One parameter of a flat layout.
struct ParamSpec {
  std::string name;
  std::vector<int64_t> shape;
};

class FlatModule : public torch::nn::Module {
 public:
  // Parameter values, (num_params()) float32.
  const torch::Tensor& flat() const { return flat_; }
  // Gradient accumulated by backward, (num_params()) float32.
  const torch::Tensor& flat_grad() const { return flat_grad_; }
  int64_t num_params() const { return flat_.numel(); }

  // The parameter views (require grad), in layout order.
  const std::vector<torch::Tensor>& params() const { return params_; }
  // Views of the same storage that do not require grad: a functional forward
  // with these computes input gradients but no weight gradients.
  const std::vector<torch::Tensor>& detached_params() const { return detached_params_; }
  const std::vector<ParamSpec>& specs() const { return specs_; }

  // Zeroes the flat gradient; re-attaches the gradient views if something
  // (e.g. Module::zero_grad(true)) replaced or cleared them.
  void ZeroGrad();
  // A replica of params() with its own gradient buffer (see GradientReplica).
  GradientReplica MakeGradientReplica() const;
  // Copies the values of a module with the same layout (e.g. target <- online).
  // Throws Error on a layout mismatch.
  void CopyFrom(const FlatModule& other);

  void save(torch::serialize::OutputArchive& archive) const override;
  void load(torch::serialize::InputArchive& archive) override;

 protected:
  explicit FlatModule(std::string name) : torch::nn::Module(std::move(name)) {}
  // Allocates the buffers and registers one view per spec. Call once, from
  // the derived constructor.
  void InitFlat(std::vector<ParamSpec> specs);

 private:
  std::vector<ParamSpec> specs_;
  torch::Tensor flat_;
  torch::Tensor flat_grad_;
  std::vector<torch::Tensor> params_;
  std::vector<torch::Tensor> detached_params_;
  std::vector<torch::Tensor> grad_views_;
};

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_FLAT_MODULE_H_
