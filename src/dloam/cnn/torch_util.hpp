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

/// Columns beyond a cut that still reach the logits next to it: the network's receptive field is
/// +-170 columns (the 3x3 and dilated 3x3 convolutions of every level at its stride); rounded up to
/// a multiple of 16 so that the parts keep the full pass's pooling grid.
inline constexpr int kPartOverlapCols = 192;

/// The same logits as forward_padded, computed on `parts` column ranges of the (padded) sweep
/// that overlap by kPartOverlapCols on each side of every cut, in parallel (TBB tasks, one
/// LibTorch thread each). One join per pass: a parallel region per layer (LibTorch's OpenMP pool)
/// stalls at every layer when another process holds a core. Equal to forward_padded up to float
/// rounding; parts = 1, or a sweep too narrow to cut, is forward_padded itself.
torch::Tensor forward_in_parts(MosNet& net, const torch::Tensor& x, int parts);

}  // namespace dloam::cnn
