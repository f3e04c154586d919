// Small LibTorch helpers shared by inference and training: bag -> tensor, and a forward pass on
// any image size (padding to the network's size multiples: columns wrap around the sweep, rows
// get zeros).
#pragma once

#include <torch/torch.h>

#include "dloam/cnn/mos_net.hpp"
#include "dloam/core/range_image_bag.hpp"

namespace dloam::cnn {

/// n rounded up to a multiple of `multiple` (the network needs rows % 8 == 0, columns % 16 == 0).
int padded_size(int n, int multiple);

/// [1, C, rows, cols] copy of the bag.
torch::Tensor bag_tensor(const RangeImageBag& bag);

/// Logits [B, 1, H, W] for x [B, C, H, W] of any H, W.
torch::Tensor forward_padded(MosNet& net, const torch::Tensor& x);

}  // namespace dloam::cnn
