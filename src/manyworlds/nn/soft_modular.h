// Soft Modularization (Yang, Xu, Wu, Wang, NeurIPS 2020), as the authors'
// network builds it (RchalYang/Soft-Module, torchrl/networks/nets.py
// ModularGatedCascadeCondNet, read as reference):
//   base      f(x): Linear(in, H) -> ReLU -> Linear(H, H) (the authors'
//             configs all use hidden_shapes [400, 400]);
//   embedding z(task) = Linear(one-hot task, H), multiplied by f(x)
//             (`cond_ob`), then the routing MLP: ReLU, routing_layers linear
//             maps of width G with ReLU between;
//   routing   p_1 = softmax(W_1 relu(z)) as an n x n matrix per row;
//             p_l = softmax(W_l relu(U_l [p_1..p_{l-1}] * z)) for the next
//             layers, and the output weights q = softmax(W_q relu(U_q
//             [p_1..p_{L-1}] * z)) over the n modules of the last layer;
//   modules   L layers of n Linear(., M) modules: layer 1 reads relu(f(x));
//             module j of layer l + 1 reads relu(sum_i p_l[j, i] out_i);
//             the output is Linear(M, out)(relu(sum_i q_i out_i)).
// Initialisation as the authors': hidden layers U(+-1/sqrt(fan_in)) with
// biases 0.1, the routing logits and the output layer U(+-3e-3).
// Differences: none in the network; the authors' batch-norm option (off in
// their configs) is not offered. Its trainer's loss reweighting by the task
// temperatures is SAC's task_reweight (sac_config.h).
#ifndef MANYWORLDS_NN_SOFT_MODULAR_H_
#define MANYWORLDS_NN_SOFT_MODULAR_H_

#include "manyworlds/nn/task_trunks.h"

namespace manyworlds::nn {

class SoftModularTrunkImpl : public TrunkImpl {
 public:
  SoftModularTrunkImpl(const TaskTrunkOptions& options, c10::optional<at::Generator> generator);
  torch::Tensor Forward(const torch::Tensor& x, const torch::Tensor& task,
                        at::ArrayRef<torch::Tensor> params) const override;
  bool uses_task() const override { return true; }
  // The routing probabilities of rows x, task: (E, B, n, n) for each of the
  // module_layers - 1 mixing steps, then the output weights (E, B, n).
  // Exposed for tests and pictures.
  std::vector<torch::Tensor> Routing(const torch::Tensor& x, const torch::Tensor& task) const;

 private:
  struct Parts;  // the parameter list cut into named pieces
  Parts Cut(at::ArrayRef<torch::Tensor> params) const;
  // f(x) before its ReLU and the routing probabilities.
  std::vector<torch::Tensor> Route(const torch::Tensor& base, const torch::Tensor& task,
                                   const Parts& parts) const;
  TaskTrunkOptions options_;
};

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_SOFT_MODULAR_H_
