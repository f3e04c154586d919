// Small LibTorch helpers shared by inference and training: bag -> tensor, and a forward pass on
// any image size (padding to the network's size multiples: columns wrap around the sweep, rows
// get zeros).
#pragma once

#include <torch/torch.h>

#include "dloam/cnn/mos_net.hpp"
#include "dloam/core/range_image_bag.hpp"

namespace dloam::cnn {

/// [1, C, rows, cols] view copy of the bag.
torch::Tensor bag_tensor(const RangeImageBag& bag);

/// Logits [B, 1, H, W] for x [B, C, H, W] of any H, W.
torch::Tensor forward_padded(MosNet& net, const torch::Tensor& x);

}  // namespace dloam::cnn
