#include "manyworlds/nn/pixel_encoder.h"

#include <cmath>
#include <string>

#include "manyworlds/core/error.h"
#include "manyworlds/nn/mlp.h"

namespace manyworlds::nn {
namespace {

constexpr double kLayerNormEps = 1e-5;  // torch::nn::LayerNorm's default, as MTRL's

// Zero but the kernel centre, which is orthogonal times sqrt(2) (ReLU's gain). weight: (a, b, 3, 3);
// the centre (a, b) is orthogonal as a matrix.
void InitDeltaOrthogonal(const torch::Tensor& weight, at::Generator& generator) {
  torch::NoGradGuard no_grad;
  weight.zero_();
  const torch::Tensor centre = weight.select(3, 1).select(2, 1);
  InitOrthogonal(centre, generator);
  centre.mul_(std::sqrt(2.0));
}

// Xavier-uniform for a (fan_in, fan_out) matrix.
void InitXavierUniform(const torch::Tensor& weight, at::Generator& generator) {
  torch::NoGradGuard no_grad;
  const double bound = std::sqrt(6.0 / static_cast<double>(weight.size(0) + weight.size(1)));
  weight.copy_((torch::rand(weight.sizes(), generator, torch::kFloat32) * 2.0 - 1.0) * bound);
}

int64_t FirstMapSide(int64_t side) { return (side - 3) / 2 + 1; }

// Row counts of frames (B, C, H, W) or (B, C * H * W) as (B, C, H, W) float.
torch::Tensor AsFrames(const torch::Tensor& frames, const std::vector<int64_t>& shape) {
  const int64_t flat = shape[0] * shape[1] * shape[2];
  const bool ok = (frames.dim() == 4 && frames.size(1) == shape[0] && frames.size(2) == shape[1] &&
                   frames.size(3) == shape[2]) ||
                  (frames.dim() == 2 && frames.size(1) == flat);
  if (!ok) {
    throw Error("PixelEncoder: frames must be (B, " + std::to_string(shape[0]) + ", " +
                std::to_string(shape[1]) + ", " + std::to_string(shape[2]) + ") or (B, " +
                std::to_string(flat) + ")");
  }
  return frames.reshape({frames.size(0), shape[0], shape[1], shape[2]}).to(torch::kFloat32);
}

}  // namespace

int64_t PixelFeatureMapSide(int64_t side, int64_t num_layers) {
  return FirstMapSide(side) - 2 * (num_layers - 1);
}

void CheckPixelEncoderOptions(const PixelEncoderOptions& o) {
  if (o.frame_shape.size() != 3 || o.frame_shape[0] < 1 || o.frame_shape[1] < 1 ||
      o.frame_shape[2] < 1) {
    throw ConfigError("pixel encoder: frames must have three positive dims (C, H, W)");
  }
  if (o.num_layers < 1 || o.num_layers > 16) {
    throw ConfigError("pixel encoder: num_conv_layers must be in [1, 16], got " +
                      std::to_string(o.num_layers));
  }
  if (o.num_filters < 1 || o.num_filters > 1024) {
    throw ConfigError("pixel encoder: num_filters must be in [1, 1024], got " +
                      std::to_string(o.num_filters));
  }
  if (o.feature_dim < 1 || o.feature_dim > 65536) {
    throw ConfigError("pixel encoder: encoder_feature_dim must be in [1, 65536], got " +
                      std::to_string(o.feature_dim));
  }
  const int64_t h = PixelFeatureMapSide(o.frame_shape[1], o.num_layers);
  const int64_t w = PixelFeatureMapSide(o.frame_shape[2], o.num_layers);
  if (o.frame_shape[1] < 3 || o.frame_shape[2] < 3 || h < 1 || w < 1) {
    throw ConfigError("pixel encoder: frames of " + std::to_string(o.frame_shape[1]) + " x " +
                      std::to_string(o.frame_shape[2]) + " are too small for " +
                      std::to_string(o.num_layers) +
                      " convolutions; use larger frames (pixel_width, pixel_height) or fewer "
                      "layers (num_conv_layers)");
  }
}

PixelEncoderImpl::PixelEncoderImpl(const PixelEncoderOptions& options, at::Generator& generator)
    : FlatModule("PixelEncoder"), options_(options) {
  CheckPixelEncoderOptions(options);
  const int64_t c = options.frame_shape[0], f = options.num_filters;
  const int64_t map = PixelFeatureMapSide(options.frame_shape[1], options.num_layers) *
                      PixelFeatureMapSide(options.frame_shape[2], options.num_layers);
  std::vector<ParamSpec> specs;
  for (int64_t l = 0; l < options.num_layers; ++l) {
    specs.push_back({"conv" + std::to_string(l) + "_w", {f, l == 0 ? c : f, 3, 3}});
    specs.push_back({"conv" + std::to_string(l) + "_b", {f}});
  }
  specs.push_back({"fc_w", {f * map, options.feature_dim}});
  specs.push_back({"fc_b", {options.feature_dim}});
  specs.push_back({"ln_w", {options.feature_dim}});
  specs.push_back({"ln_b", {options.feature_dim}});
  InitFlat(std::move(specs));
  torch::NoGradGuard no_grad;
  const auto& p = params();
  for (int64_t l = 0; l < options.num_layers; ++l) {
    InitDeltaOrthogonal(p[2 * l], generator);
    p[2 * l + 1].zero_();
  }
  const size_t fc = 2 * static_cast<size_t>(options.num_layers);
  InitXavierUniform(p[fc], generator);
  p[fc + 1].zero_();
  p[fc + 2].fill_(1.0);
  p[fc + 3].zero_();
}

torch::Tensor PixelEncoderImpl::Forward(const torch::Tensor& frames,
                                        at::ArrayRef<torch::Tensor> params) const {
  torch::Tensor x = AsFrames(frames, options_.frame_shape) / 255.0;
  for (int64_t l = 0; l < options_.num_layers; ++l) {
    x = torch::relu(torch::conv2d(x, params[2 * l], params[2 * l + 1], l == 0 ? 2 : 1));
  }
  const size_t fc = 2 * static_cast<size_t>(options_.num_layers);
  x = torch::addmm(params[fc + 1], x.flatten(1), params[fc]);
  x = torch::layer_norm(x, {options_.feature_dim}, params[fc + 2], params[fc + 3], kLayerNormEps);
  return torch::tanh(x);
}

PixelDecoderImpl::PixelDecoderImpl(const PixelEncoderOptions& options, int64_t input_dim,
                                   at::Generator& generator)
    : FlatModule("PixelDecoder"), options_(options) {
  CheckPixelEncoderOptions(options);
  if (input_dim < 1) throw ConfigError("pixel decoder: input_dim must be >= 1");
  const int64_t c = options.frame_shape[0], f = options.num_filters;
  map_h_ = PixelFeatureMapSide(options.frame_shape[1], options.num_layers);
  map_w_ = PixelFeatureMapSide(options.frame_shape[2], options.num_layers);
  std::vector<ParamSpec> specs = {{"fc_w", {input_dim, f * map_h_ * map_w_}},
                                  {"fc_b", {f * map_h_ * map_w_}}};
  for (int64_t l = 0; l < options.num_layers; ++l) {
    const bool last = l + 1 == options.num_layers;
    // conv_transpose2d weights are (in, out, k, k)
    specs.push_back({"deconv" + std::to_string(l) + "_w", {f, last ? c : f, 3, 3}});
    specs.push_back({"deconv" + std::to_string(l) + "_b", {last ? c : f}});
  }
  InitFlat(std::move(specs));
  torch::NoGradGuard no_grad;
  const auto& p = params();
  InitXavierUniform(p[0], generator);
  p[1].zero_();
  for (int64_t l = 0; l < options.num_layers; ++l) {
    InitDeltaOrthogonal(p[2 + 2 * l], generator);
    p[3 + 2 * l].zero_();
  }
}

torch::Tensor PixelDecoderImpl::Forward(const torch::Tensor& h,
                                        at::ArrayRef<torch::Tensor> params) const {
  const int64_t f = options_.num_filters;
  torch::Tensor x = torch::relu(torch::addmm(params[1], h, params[0]));
  x = x.reshape({h.size(0), f, map_h_, map_w_});
  for (int64_t l = 0; l + 1 < options_.num_layers; ++l) {
    x = torch::relu(torch::conv_transpose2d(x, params[2 + 2 * l], params[3 + 2 * l], 1));
  }
  // (side - 1) * 2 + 3 + padding = the frame side
  const int64_t l = options_.num_layers - 1;
  const int64_t pad_h = options_.frame_shape[1] - 2 * FirstMapSide(options_.frame_shape[1]) - 1;
  const int64_t pad_w = options_.frame_shape[2] - 2 * FirstMapSide(options_.frame_shape[2]) - 1;
  return torch::conv_transpose2d(x, params[2 + 2 * l], params[3 + 2 * l], 2, 0, {pad_h, pad_w});
}

torch::Tensor PreprocessFrames(const torch::Tensor& frames, at::Generator& generator) {
  const torch::Tensor x = torch::floor(frames.to(torch::kFloat32) / 8.0) / 32.0;
  return x + torch::rand(x.sizes(), generator, torch::kFloat32) / 32.0 - 0.5;
}

}  // namespace manyworlds::nn
