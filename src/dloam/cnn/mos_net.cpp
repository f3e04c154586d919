#include "dloam/cnn/mos_net.hpp"

#include <filesystem>

#include "dloam/core/types.hpp"

namespace dloam::cnn {

namespace nn = torch::nn;

ConvBnImpl::ConvBnImpl(int in, int out, int kernel, int dilation, int stride_w)
    : pad_(dilation * (kernel / 2)), dilation_(dilation), stride_w_(stride_w) {
  conv = register_module("conv", nn::Conv2d(nn::Conv2dOptions(in, out, kernel)
                                                .padding(pad_)
                                                .dilation(dilation)
                                                .stride({1, stride_w})
                                                .bias(false)));
  bn = register_module("bn", nn::BatchNorm2d(out));
}

torch::Tensor ConvBnImpl::forward(const torch::Tensor& x) {
  if (folded_weight_.defined()) {
    if (is_training()) throw std::logic_error("ConvBn: batch norm folded for inference, cannot train");
    torch::Tensor y =
        torch::conv2d(x, folded_weight_, folded_bias_, {1, stride_w_}, {pad_, pad_}, {dilation_, dilation_});
    return torch::leaky_relu_(y, 0.01);
  }
  return torch::leaky_relu(bn->forward(conv->forward(x)), 0.01);
}

void ConvBnImpl::fold_batch_norm(torch::MemoryFormat format) {
  torch::NoGradGuard no_grad;
  const torch::Tensor scale = bn->weight / torch::sqrt(bn->running_var + bn->options.eps());
  folded_weight_ = (conv->weight * scale.view({-1, 1, 1, 1})).contiguous(format);
  folded_bias_ = (bn->bias - bn->running_mean * scale).contiguous();
}

ResBlockImpl::ResBlockImpl(int in, int out) {
  shortcut = register_module("shortcut", ConvBn(in, out, 1));
  a = register_module("a", ConvBn(out, out, 3));
  b = register_module("b", ConvBn(out, out, 3, 2));
}

torch::Tensor ResBlockImpl::forward(const torch::Tensor& x) {
  const torch::Tensor s = shortcut->forward(x);
  return s + b->forward(a->forward(s));
}

UpBlockImpl::UpBlockImpl(int in, int skip, int out) {
  fuse = register_module("fuse", ConvBn(in / 4 + skip, out, 1));
  refine = register_module("refine", ConvBn(out, out, 3, 2));
}

torch::Tensor UpBlockImpl::forward(const torch::Tensor& x, const torch::Tensor& skip) {
  const torch::Tensor up = torch::pixel_shuffle(x, 2);
  const torch::Tensor f = fuse->forward(torch::cat({up, skip}, 1));
  return f + refine->forward(f);
}

MosNetImpl::MosNetImpl(const MosNetOptions& o) : options(o) {
  const int w = o.width;
  stem = register_module("stem", ConvBn(5 + o.m, w, 3, 1, 2));
  enc1 = register_module("enc1", ResBlock(w, 2 * w));
  enc2 = register_module("enc2", ResBlock(2 * w, 4 * w));
  enc3 = register_module("enc3", ResBlock(4 * w, 4 * w));
  mid = register_module("mid", ResBlock(4 * w, 4 * w));
  dec3 = register_module("dec3", UpBlock(4 * w, 4 * w, 4 * w));
  dec2 = register_module("dec2", UpBlock(4 * w, 2 * w, 2 * w));
  dec1 = register_module("dec1", UpBlock(2 * w, w, w));
  head =
      register_module("head", nn::ConvTranspose2d(nn::ConvTranspose2dOptions(w, 1, {1, 2}).stride({1, 2})));
}

torch::Tensor MosNetImpl::forward(const torch::Tensor& x) {
  const torch::Tensor s0 = stem->forward(x);                                       // H   x W/2,  w
  const torch::Tensor s1 = enc1->forward(torch::avg_pool2d(s0, 2));                // H/2 x W/4,  2w
  const torch::Tensor s2 = enc2->forward(torch::avg_pool2d(s1, 2));                // H/4 x W/8,  4w
  const torch::Tensor s3 = mid->forward(enc3->forward(torch::avg_pool2d(s2, 2)));  // H/8 x W/16, 4w
  torch::Tensor d = dec3->forward(s3, s2);
  d = dec2->forward(d, s1);
  d = dec1->forward(d, s0);
  return head->forward(d);
}

void MosNetImpl::prepare_for_inference(torch::MemoryFormat format) {
  eval();
  for (const auto& module : modules(/*include_self=*/false))
    if (auto* c = dynamic_cast<ConvBnImpl*>(module.get())) c->fold_batch_norm(format);
  torch::NoGradGuard no_grad;
  for (auto& p : head->parameters())
    if (p.dim() == 4) p.set_data(p.contiguous(format));
}

std::int64_t parameter_count(MosNet& net) {
  std::int64_t n = 0;
  for (const auto& p : net->parameters()) n += p.numel();
  return n;
}

void save_mos_net(MosNet& net, const std::string& path) {
  torch::serialize::OutputArchive archive;
  archive.write("m", torch::tensor(static_cast<std::int64_t>(net->options.m)));
  archive.write("width", torch::tensor(static_cast<std::int64_t>(net->options.width)));
  archive.write("trained_rows", torch::tensor(static_cast<std::int64_t>(net->options.trained_rows)));
  archive.write("trained_cols", torch::tensor(static_cast<std::int64_t>(net->options.trained_cols)));
  net->save(archive);
  const std::string tmp = path + ".tmp";  // atomic: an interrupted save never leaves a broken model
  archive.save_to(tmp);
  std::filesystem::rename(tmp, path);
}

namespace {
torch::serialize::InputArchive open_archive(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": model file not found");
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path);
  } catch (const std::exception& e) {
    throw InputError(path + ": not a dloam CNN model file (" + std::string(e.what()).substr(0, 200) + ")");
  }
  return archive;
}

MosNetOptions read_options(torch::serialize::InputArchive& archive, const std::string& path) {
  torch::Tensor m, width, rows, cols;
  if (!archive.try_read("m", m) || !archive.try_read("width", width))
    throw InputError(path + ": model file without the 'm' / 'width' entries");
  MosNetOptions o;
  o.m = static_cast<int>(m.item<std::int64_t>());
  o.width = static_cast<int>(width.item<std::int64_t>());
  if (archive.try_read("trained_rows", rows) && archive.try_read("trained_cols", cols)) {
    o.trained_rows = static_cast<int>(rows.item<std::int64_t>());
    o.trained_cols = static_cast<int>(cols.item<std::int64_t>());
  }
  return o;
}
}  // namespace

MosNetOptions read_mos_net_options(const std::string& path) {
  torch::serialize::InputArchive archive = open_archive(path);
  return read_options(archive, path);
}

MosNet load_mos_net(const std::string& path) {
  torch::serialize::InputArchive archive = open_archive(path);
  const MosNetOptions o = read_options(archive, path);
  MosNet net(o);
  try {
    net->load(archive);
  } catch (const std::exception& e) {
    throw InputError(path + ": weights do not match MosNet(m=" + std::to_string(o.m) +
                     ", width=" + std::to_string(o.width) + "): " + std::string(e.what()).substr(0, 200));
  }
  return net;
}

}  // namespace dloam::cnn
