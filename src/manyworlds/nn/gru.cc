#include "manyworlds/nn/gru.h"

#include <cmath>
#include <string>
#include <vector>

#include "manyworlds/core/error.h"

namespace manyworlds::nn {

GruImpl::GruImpl(int64_t input_dim, int64_t hidden_dim, at::Generator& generator)
    : FlatModule("Gru"), input_dim_(input_dim), hidden_dim_(hidden_dim) {
  if (input_dim <= 0 || hidden_dim <= 0) {
    throw ConfigError("GRU: input and hidden sizes must be > 0, got " +
                      std::to_string(input_dim) + ", " + std::to_string(hidden_dim));
  }
  InitFlat({{"w_ih", {3 * hidden_dim, input_dim}},
            {"w_hh", {3 * hidden_dim, hidden_dim}},
            {"b_ih", {3 * hidden_dim}},
            {"b_hh", {3 * hidden_dim}}});
  torch::NoGradGuard no_grad;
  const double bound = 1.0 / std::sqrt(static_cast<double>(hidden_dim));
  for (const torch::Tensor& p : detached_params()) p.uniform_(-bound, bound, generator);
}

std::pair<torch::Tensor, torch::Tensor> GruImpl::Forward(const torch::Tensor& x,
                                                         const torch::Tensor& h0) const {
  if (x.dim() != 3 || x.size(2) != input_dim_ || h0.dim() != 2 || h0.size(0) != x.size(1) ||
      h0.size(1) != hidden_dim_) {
    throw Error("GRU: expected x (T, N, " + std::to_string(input_dim_) + ") and h0 (N, " +
                std::to_string(hidden_dim_) + ")");
  }
  auto [out, h] = at::gru(x, h0.unsqueeze(0), params(), /*has_biases=*/true, /*num_layers=*/1,
                          /*dropout=*/0.0, /*train=*/false, /*bidirectional=*/false,
                          /*batch_first=*/false);
  return {out, h.squeeze(0)};
}

}  // namespace manyworlds::nn
