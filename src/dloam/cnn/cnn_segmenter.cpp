#include "dloam/cnn/cnn_segmenter.hpp"

#include <filesystem>
#include <mutex>

#include "dloam/cnn/mos_net.hpp"
#include "dloam/cnn/torch_util.hpp"
#include "dloam/pipeline/detector_choice.hpp"

namespace dloam::cnn {

namespace {

class CnnSegmenter final : public MovingSegmenter {
 public:
  CnnSegmenter(MosNet net, int parts) : net_(std::move(net)), parts_(std::max(1, parts)) {
    // Channels-last weights and input take oneDNN's direct convolutions: ~20 % faster on the CPU.
    net_->prepare_for_inference(torch::MemoryFormat::ChannelsLast);
  }
  [[nodiscard]] int m() const override { return net_->options.m; }

  std::vector<float> moving_probability(const RangeImageBag& bag) override {
    if (bag.channels != 5 + m())
      throw std::invalid_argument("CNN: bag of " + std::to_string(bag.channels) +
                                  " channels, the model takes " + std::to_string(5 + m()));
    torch::NoGradGuard no_grad;
    const torch::Tensor logits =
        forward_in_parts(net_, bag_tensor(bag).contiguous(torch::MemoryFormat::ChannelsLast), parts_);
    const torch::Tensor p = torch::sigmoid(logits).contiguous();
    const float* data = p.data_ptr<float>();
    return {data, data + static_cast<std::ptrdiff_t>(bag.rows) * bag.cols};
  }

 private:
  MosNet net_;
  int parts_;
};

}  // namespace

std::string resolve_model_path(const DetectionConfig& detection, const std::string& model_dir) {
  if (!detection.model_path.empty()) return detection.model_path;
  return model_dir + "/mos_m" + std::to_string(detection.m) + ".pt";
}

std::shared_ptr<MovingSegmenter> prepare_detector(DetectionConfig& detection, const std::string& model_dir,
                                                  const SensorConfig& sensor, const std::string& platform,
                                                  std::string* note) {
  const std::string path = resolve_model_path(detection, model_dir);
  CnnModelInfo model;
  model.path = path;
  // An explicit cnn with a missing file goes on to the load, whose error names the file.
  model.available = std::filesystem::exists(path) || detection.detector == Detector::kCnn;
  if (std::filesystem::exists(path) && detection.detector != Detector::kNone &&
      detection.detector != Detector::kGeometric) {
    const MosNetOptions o = read_mos_net_options(path);
    model.trained_rows = o.trained_rows;
    model.trained_cols = o.trained_cols;
  }
  const DetectorChoice choice = choose_detector(detection.detector, model, sensor, platform);
  detection.detector = choice.detector;
  if (note) *note = choice.note;
  if (detection.detector != Detector::kCnn) return nullptr;
  detection.model_path = path;
  return load_cnn_segmenter(detection.model_path, detection.threads, detection.m);
}

std::unique_ptr<MovingSegmenter> load_cnn_segmenter(const std::string& model_path, int threads,
                                                    int expected_m) {
  // One LibTorch thread: the parallelism is forward_in_parts' (one join per scan, TBB's sleeping
  // workers), not an OpenMP region per layer that spins and stalls when another process holds a core.
  static std::once_flag once;
  std::call_once(once, [] { torch::set_num_threads(1); });
  auto net = std::make_unique<CnnSegmenter>(load_mos_net(model_path), threads);
  if (expected_m >= 0 && net->m() != expected_m)
    throw InputError(model_path + ": the model takes m = " + std::to_string(net->m()) +
                     " speed images, the config says detection.m = " + std::to_string(expected_m));
  return net;
}

}  // namespace dloam::cnn
