// MosNet: a small SalsaNext-style encoder-decoder for moving-object segmentation on the range
// image bag (paper III.D.3.b, Fig. 4). Residual blocks with dilated 3x3 convolutions (SalsaNext's
// context and residual blocks), average-pool downsampling, pixel-shuffle upsampling with skip
// connections, one moving logit per pixel. The stem halves the width (64x2048 -> 64x1024) and the
// last layer restores it, so the bulk of the work runs on a quarter of the pixels: the budget is
// well under 50 ms per 64x2048 bag on two cores.
// This header pulls in LibTorch: only the cnn/ translation units include it.
#pragma once

#include <torch/torch.h>

#include <string>

namespace dloam::cnn {

struct MosNetOptions {
  int m = 6;       ///< speed images in the bag (input channels = 5 + m)
  int width = 16;  ///< channels of the first level; levels use width, 2w, 4w, 4w
  /// Range-image size of the training data (N_scan x Horizon_SCAN); 0 when the file predates it.
  /// The network runs on any size, but a 64-beam model on a 16-beam sensor segments poorly.
  int trained_rows = 0, trained_cols = 0;
};

/// 3x3 (or 1x1) convolution + batch norm + leaky ReLU.
struct ConvBnImpl : torch::nn::Module {
  ConvBnImpl(int in, int out, int kernel, int dilation = 1, int stride_w = 1);
  torch::Tensor forward(const torch::Tensor& x);
  /// Inference only: folds the batch norm's running statistics into one convolution with a bias
  /// (w' = w * gamma / sqrt(var + eps), b' = beta - mean * gamma / sqrt(var + eps)), saving a pass
  /// over the activations. The saved weights are untouched; training after this is an error.
  void fold_batch_norm(torch::MemoryFormat format);
  torch::nn::Conv2d conv{nullptr};
  torch::nn::BatchNorm2d bn{nullptr};

 private:
  torch::Tensor folded_weight_, folded_bias_;
  std::int64_t pad_ = 0, dilation_ = 1, stride_w_ = 1;
};
TORCH_MODULE(ConvBn);

/// SalsaNext-style residual block: 1x1 shortcut + (3x3 -> 3x3 dilated 2).
struct ResBlockImpl : torch::nn::Module {
  ResBlockImpl(int in, int out);
  torch::Tensor forward(const torch::Tensor& x);
  ConvBn shortcut{nullptr}, a{nullptr}, b{nullptr};
};
TORCH_MODULE(ResBlock);

/// Decoder block: pixel shuffle x2, concatenate the skip, 1x1 fuse, dilated residual 3x3.
struct UpBlockImpl : torch::nn::Module {
  UpBlockImpl(int in, int skip, int out);
  torch::Tensor forward(const torch::Tensor& x, const torch::Tensor& skip);
  ConvBn fuse{nullptr}, refine{nullptr};
};
TORCH_MODULE(UpBlock);

struct MosNetImpl : torch::nn::Module {
  explicit MosNetImpl(const MosNetOptions& options);
  /// x: [B, 5 + m, H, W] (H divisible by 8, W by 16) -> moving logits [B, 1, H, W].
  torch::Tensor forward(const torch::Tensor& x);
  MosNetOptions options;
  ConvBn stem{nullptr};
  ResBlock enc1{nullptr}, enc2{nullptr}, enc3{nullptr}, mid{nullptr};
  UpBlock dec3{nullptr}, dec2{nullptr}, dec1{nullptr};
  torch::nn::ConvTranspose2d head{nullptr};
  /// Inference only: eval mode, every ConvBn's batch norm folded into its convolution, weights in
  /// `format` (channels-last takes oneDNN's direct convolutions on the CPU).
  void prepare_for_inference(torch::MemoryFormat format = torch::MemoryFormat::ChannelsLast);
};
TORCH_MODULE(MosNet);

/// Number of trainable parameters.
std::int64_t parameter_count(MosNet& net);
/// Saves / loads the weights with the options (m, width) so a file is self-describing.
void save_mos_net(MosNet& net, const std::string& path);
MosNet load_mos_net(const std::string& path);
/// The options stored in a model file (m, width, training image size) without building the net.
MosNetOptions read_mos_net_options(const std::string& path);

}  // namespace dloam::cnn
