#include "dloam/cnn/cnn_segmenter.hpp"

#include <filesystem>
#include <mutex>

#include "dloam/cnn/mos_net.hpp"
#include "dloam/cnn/torch_util.hpp"

namespace dloam::cnn {

namespace {

class CnnSegmenter final : public MovingSegmenter {
 public:
  explicit CnnSegmenter(MosNet net) : net_(std::move(net)) {
    net_->eval();
    // Channels-last weights and input take oneDNN's direct convolutions: ~20 % faster on the CPU.
    for (auto& p : net_->parameters())
      if (p.dim() == 4) p.set_data(p.contiguous(torch::MemoryFormat::ChannelsLast));
  }
  [[nodiscard]] int m() const override { return net_->options.m; }

  std::vector<float> moving_probability(const RangeImageBag& bag) override {
    if (bag.channels != 5 + m())
      throw std::invalid_argument("CNN: bag of " + std::to_string(bag.channels) +
                                  " channels, the model takes " + std::to_string(5 + m()));
    torch::NoGradGuard no_grad;
    const torch::Tensor logits =
        forward_padded(net_, bag_tensor(bag).contiguous(torch::MemoryFormat::ChannelsLast));
    const torch::Tensor p = torch::sigmoid(logits).contiguous();
    const float* data = p.data_ptr<float>();
    return {data, data + static_cast<std::ptrdiff_t>(bag.rows) * bag.cols};
  }

 private:
  MosNet net_;
};

}  // namespace

std::string resolve_model_path(const DetectionConfig& detection, const std::string& model_dir) {
  if (!detection.model_path.empty()) return detection.model_path;
  return model_dir + "/mos_m" + std::to_string(detection.m) + ".pt";
}

std::shared_ptr<MovingSegmenter> prepare_detector(DetectionConfig& detection, const std::string& model_dir,
                                                  const SensorConfig& sensor, std::string* note) {
  const std::string path = resolve_model_path(detection, model_dir);
  const bool have_model = std::filesystem::exists(path);
  std::string mismatch;  // the model's training image size when it is not this sensor's
  if ((detection.detector == "auto" || detection.detector == "cnn") && have_model) {
    const MosNetOptions o = read_mos_net_options(path);
    if (o.trained_rows > 0 && (o.trained_rows != sensor.N_scan || o.trained_cols != sensor.Horizon_SCAN))
      mismatch = path + " was trained on " + std::to_string(o.trained_rows) + " x " +
                 std::to_string(o.trained_cols) + " range images, this sensor gives " +
                 std::to_string(sensor.N_scan) + " x " + std::to_string(sensor.Horizon_SCAN);
  }
  if (detection.detector == "auto") {
    detection.detector = have_model && mismatch.empty() ? "cnn" : "geometric";
    if (note && !mismatch.empty()) *note = mismatch + ": detector auto uses the geometric detector";
  } else if (detection.detector == "cnn" && note && !mismatch.empty()) {
    *note = "warning: " + mismatch + "; its moving-object segmentation may be poor";
  }
  if (detection.detector != "cnn") return nullptr;
  detection.model_path = path;
  return load_cnn_segmenter(detection.model_path, detection.threads, detection.m);
}

std::unique_ptr<MovingSegmenter> load_cnn_segmenter(const std::string& model_path, int threads,
                                                    int expected_m) {
  static std::once_flag once;
  std::call_once(once, [threads] { torch::set_num_threads(std::max(1, threads)); });
  auto net = std::make_unique<CnnSegmenter>(load_mos_net(model_path));
  if (expected_m >= 0 && net->m() != expected_m)
    throw InputError(model_path + ": the model takes m = " + std::to_string(net->m()) +
                     " speed images, the config says detection.m = " + std::to_string(expected_m));
  return net;
}

}  // namespace dloam::cnn
