#include "dloam/cnn/torch_util.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <vector>

namespace dloam::cnn {

int padded_size(int n, int multiple) { return (n + multiple - 1) / multiple * multiple; }

torch::Tensor bag_tensor(const RangeImageBag& bag) {
  return torch::from_blob(const_cast<float*>(bag.data.data()), {1, bag.channels, bag.rows, bag.cols},
                          torch::kFloat32)
      .clone();
}

namespace {
/// x padded to the network's multiples: columns wrap around the sweep, rows get zeros.
torch::Tensor pad_to_network(const torch::Tensor& x) {
  const auto H = x.size(2), W = x.size(3);
  const auto Hp = padded_size(static_cast<int>(H), 8), Wp = padded_size(static_cast<int>(W), 16);
  torch::Tensor in = x;
  if (Wp > W) in = torch::cat({in, in.slice(3, 0, Wp - W)}, 3);
  if (Hp > H) in = torch::constant_pad_nd(in, {0, 0, 0, Hp - H});
  return in;
}
}  // namespace

torch::Tensor forward_padded(MosNet& net, const torch::Tensor& x) {
  const auto H = x.size(2), W = x.size(3);
  torch::Tensor out = net->forward(pad_to_network(x));
  return out.slice(2, 0, H).slice(3, 0, W);
}

torch::Tensor forward_in_parts(MosNet& net, const torch::Tensor& x, int parts) {
  const auto H = x.size(2), W = x.size(3);
  const std::int64_t Wp = padded_size(static_cast<int>(W), 16);
  // Cuts on the 16-column grid, each part at least two overlaps wide.
  const auto n = std::clamp<std::int64_t>(Wp / (4 * kPartOverlapCols), 1, std::max(1, parts));
  if (n <= 1) return forward_padded(net, x);
  const torch::Tensor in = pad_to_network(x);
  std::vector<std::int64_t> cut(static_cast<std::size_t>(n) + 1, 0);
  for (std::int64_t k = 1; k < n; ++k) cut[static_cast<std::size_t>(k)] = Wp * k / n / 16 * 16;
  cut.back() = Wp;
  std::vector<torch::Tensor> logits(static_cast<std::size_t>(n));
  tbb::parallel_for(std::int64_t{0}, n, [&](std::int64_t k) {
    torch::NoGradGuard no_grad;  // thread-local: each task sets its own
    const auto i = static_cast<std::size_t>(k);
    const std::int64_t a = std::max<std::int64_t>(0, cut[i] - kPartOverlapCols);
    const std::int64_t b = std::min<std::int64_t>(Wp, cut[i + 1] + kPartOverlapCols);
    const torch::Tensor part = net->forward(in.slice(3, a, b).contiguous(in.suggest_memory_format()));
    logits[i] = part.slice(3, cut[i] - a, cut[i + 1] - a);
  });
  return torch::cat(logits, 3).slice(2, 0, H).slice(3, 0, W);
}

}  // namespace dloam::cnn
