#include "dloam/cnn/torch_util.hpp"

namespace dloam::cnn {

int padded_size(int n, int multiple) { return (n + multiple - 1) / multiple * multiple; }

torch::Tensor bag_tensor(const RangeImageBag& bag) {
  return torch::from_blob(const_cast<float*>(bag.data.data()), {1, bag.channels, bag.rows, bag.cols},
                          torch::kFloat32)
      .clone();
}

torch::Tensor forward_padded(MosNet& net, const torch::Tensor& x) {
  const auto H = x.size(2), W = x.size(3);
  const auto Hp = padded_size(static_cast<int>(H), 8), Wp = padded_size(static_cast<int>(W), 16);
  torch::Tensor in = x;
  if (Wp > W) in = torch::cat({in, in.slice(3, 0, Wp - W)}, 3);
  if (Hp > H) in = torch::constant_pad_nd(in, {0, 0, 0, Hp - H});
  torch::Tensor out = net->forward(in);
  if (Hp > H || Wp > W) out = out.slice(2, 0, H).slice(3, 0, W);
  return out;
}

}  // namespace dloam::cnn
