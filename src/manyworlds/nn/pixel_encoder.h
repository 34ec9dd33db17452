// Convolutional encoder and decoder of pixel observations (SAC-AE's, as MTRL
// builds them for its pixel agents: sac, sac_ae, deepmdp, hipbmdp).
//
// Encoder: frames (B, C, H, W) uint8 -> /255 -> num_layers 3x3 convolutions
// with num_filters channels, the first of stride 2, the others of stride 1,
// each followed by ReLU -> flatten -> Linear(feature_dim) -> LayerNorm -> tanh.
// On MTEnv's 84 x 84 frames 4 layers give 35 x 35 maps, MTRL's hard-coded
// {2: 39, 4: 35, 6: 31}; here the size follows from the frame size, so
// smaller frames work too.
// Decoder: the mirror image, features -> Linear -> ReLU -> (num_layers - 1)
// stride-1 transposed convolutions with ReLU -> one of stride 2 back to
// (C, H, W) (output padding chosen to land on H and W exactly), no output
// nonlinearity: it predicts frames preprocessed to [-0.5, 0.5].
//
// Initialisation as MTRL's weight_init: convolutions delta-orthogonal (zero
// but the kernel centre, orthogonal with ReLU gain sqrt(2)), linear layers
// Xavier-uniform, zero biases, LayerNorm gain 1, bias 0. Every draw comes
// from the caller's generator.
#ifndef MANYWORLDS_NN_PIXEL_ENCODER_H_
#define MANYWORLDS_NN_PIXEL_ENCODER_H_

#include <cstdint>
#include <vector>

#include <torch/torch.h>

#include "manyworlds/nn/flat_module.h"

namespace manyworlds::nn {

struct PixelEncoderOptions {
  std::vector<int64_t> frame_shape;  // (C, H, W), e.g. (9, 84, 84) for 3 stacked RGB frames
  int64_t num_layers = 4;            // convolutions (MTRL: 4)
  int64_t num_filters = 32;          // channels of every convolution (MTRL: 32)
  int64_t feature_dim = 50;          // MTRL's encoder_feature_dim
};

// Throws ConfigError naming the field unless the options describe a network
// (three positive frame dims, layers >= 1, filters and features >= 1, a
// frame large enough for the layers: H and W >= 2 * num_layers + 1).
void CheckPixelEncoderOptions(const PixelEncoderOptions& options);
// Side of the last feature map for a frame side (H or W).
int64_t PixelFeatureMapSide(int64_t side, int64_t num_layers);

class PixelEncoderImpl : public FlatModule {
 public:
  PixelEncoderImpl(const PixelEncoderOptions& options, at::Generator& generator);

  // frames: (B, C, H, W) or (B, C * H * W), uint8 (or float in [0, 255]);
  // -> (B, feature_dim) in (-1, 1). Differentiable in `params` (params(),
  // detached_params() or a GradientReplica's).
  torch::Tensor Forward(const torch::Tensor& frames, at::ArrayRef<torch::Tensor> params) const;
  torch::Tensor forward(const torch::Tensor& frames) { return Forward(frames, params()); }

  const PixelEncoderOptions& options() const { return options_; }
  int64_t feature_dim() const { return options_.feature_dim; }

 private:
  PixelEncoderOptions options_;
};
TORCH_MODULE(PixelEncoder);

class PixelDecoderImpl : public FlatModule {
 public:
  // input_dim: the width of what it decodes (the encoder's features, plus a
  // task encoding where one is concatenated).
  PixelDecoderImpl(const PixelEncoderOptions& options, int64_t input_dim,
                   at::Generator& generator);

  // h (B, input_dim) -> frames (B, C, H, W) float in the preprocessed scale.
  torch::Tensor Forward(const torch::Tensor& h, at::ArrayRef<torch::Tensor> params) const;
  torch::Tensor forward(const torch::Tensor& h) { return Forward(h, params()); }

 private:
  PixelEncoderOptions options_;
  int64_t map_h_ = 0, map_w_ = 0;  // the encoder's last feature map
};
TORCH_MODULE(PixelDecoder);

// SAC-AE's reconstruction target (MTRL's preprocess_obs with 5 bits):
// frames (B, C, H, W) or flat, uint8 -> floor(x / 8) / 32 + U(0, 1/32) - 0.5,
// the uniform dequantisation noise drawn from `generator`.
torch::Tensor PreprocessFrames(const torch::Tensor& frames, at::Generator& generator);

}  // namespace manyworlds::nn

#endif  // MANYWORLDS_NN_PIXEL_ENCODER_H_
