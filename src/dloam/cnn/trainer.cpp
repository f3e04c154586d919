#include "dloam/cnn/trainer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "dloam/cnn/mos_net.hpp"
#include "dloam/cnn/torch_util.hpp"

namespace dloam::cnn {

namespace {

/// Pixel confusion of the moving class (labelled pixels only), each pixel counted with its
/// sequence's weight.
struct PixelScore {
  double tp = 0, fp = 0, fn = 0;
  [[nodiscard]] double iou() const { return tp + fp + fn > 0 ? tp / (tp + fp + fn) : 0.0; }
};

struct FrameRef {
  std::size_t seq = 0, frame = 0;
};

struct Split {
  std::vector<FrameRef> train, val;
};

/// One epoch's training draws: `shuffled` with every frame of a sequence of weight w drawn
/// floor(w) times and once more with probability w - floor(w), shuffled again. With all weights
/// 1 that is `shuffled` itself (and no random number is drawn).
std::vector<FrameRef> epoch_draws(const std::vector<MosSequence>& data, const std::vector<FrameRef>& shuffled,
                                  std::mt19937& rng) {
  const bool unweighted =
      std::all_of(data.begin(), data.end(), [](const MosSequence& q) { return q.weight == 1.0; });
  if (unweighted) return shuffled;
  std::vector<FrameRef> order;
  for (const FrameRef& r : shuffled) {
    const double w = data[r.seq].weight;
    const double whole = std::floor(w);
    auto n = static_cast<std::size_t>(whole);
    if (w > whole && std::uniform_real_distribution<double>(0.0, 1.0)(rng) < w - whole) ++n;
    order.insert(order.end(), n, r);
  }
  std::shuffle(order.begin(), order.end(), rng);
  return order;
}

Split split_frames(const std::vector<MosSequence>& data, const TrainOptions& o) {
  Split s;
  for (std::size_t q = 0; q < data.size(); ++q) {
    const std::size_t n = data[q].frames.size();
    const auto n_val = static_cast<std::size_t>(std::round(o.val_fraction * static_cast<double>(n)));
    // A gap of m frames keeps validation scans out of the training bags' past.
    const std::size_t val_start = n - n_val;
    const std::size_t train_end =
        n_val > 0 ? (val_start > static_cast<std::size_t>(o.m) ? val_start - o.m : 0) : n;
    for (std::size_t k = 0; k < train_end; ++k) s.train.push_back({q, k});
    for (std::size_t k = val_start; k < n; k += static_cast<std::size_t>(std::max(1, o.val_stride)))
      s.val.push_back({q, k});
  }
  return s;
}

torch::Tensor target_tensor(const MosFrame& f) {
  torch::Tensor t = torch::empty({1, 1, f.image.rows, f.image.cols}, torch::kUInt8);
  std::copy(f.target.begin(), f.target.end(), t.data_ptr<std::uint8_t>());
  return t;
}

/// Weighted BCE on labelled pixels + (1 - soft IoU) of the moving class.
torch::Tensor mos_loss(const torch::Tensor& logits, const torch::Tensor& target, double pos_weight) {
  const torch::Tensor valid = (target != kTargetIgnore).to(torch::kFloat32);
  const torch::Tensor y = (target == kTargetMoving).to(torch::kFloat32);
  const torch::Tensor w = valid * (1.0 + (pos_weight - 1.0) * y);
  const torch::Tensor bce = torch::binary_cross_entropy_with_logits(logits, y, w, {}, at::Reduction::Sum) /
                            valid.sum().clamp_min(1.0);
  const torch::Tensor p = torch::sigmoid(logits) * valid;
  const torch::Tensor inter = (p * y).sum();
  const torch::Tensor uni = (p + y - p * y).sum();
  return bce + (1.0 - (inter + 1.0) / (uni + 1.0));
}

PixelScore score(MosNet& net, const std::vector<MosSequence>& data, const std::vector<FrameRef>& frames,
                 int m) {
  torch::NoGradGuard no_grad;
  net->eval();
  PixelScore s;
  for (const FrameRef& r : frames) {
    const MosFrame& f = data[r.seq].frames[r.frame];
    const RangeImageBag bag = sample_bag(data[r.seq], r.frame, m, {}, nullptr);
    const torch::Tensor pred = (forward_padded(net, bag_tensor(bag)) > 0.0).contiguous();
    const bool* p = pred.data_ptr<bool>();
    std::size_t tp = 0, fp = 0, fn = 0;
    for (std::size_t px = 0; px < f.target.size(); ++px) {
      if (f.target[px] == kTargetIgnore) continue;
      const bool gt = f.target[px] == kTargetMoving;
      tp += (p[px] && gt);
      fp += (p[px] && !gt);
      fn += (!p[px] && gt);
    }
    const double w = data[r.seq].weight;
    s.tp += w * static_cast<double>(tp);
    s.fp += w * static_cast<double>(fp);
    s.fn += w * static_cast<double>(fn);
  }
  net->train();
  return s;
}

}  // namespace

std::vector<EpochReport> train_mos_net(const std::vector<MosSequence>& data, const SensorConfig& sensor,
                                       const TrainOptions& o, const TrainCallbacks& cb) {
  torch::set_num_threads(std::max(1, o.threads));
  torch::manual_seed(o.seed);
  std::mt19937 rng(o.seed);
  const Split split = split_frames(data, o);
  if (split.train.empty()) throw std::invalid_argument("train: no training frames");
  if (o.crop_cols % 16 != 0) throw std::invalid_argument("train: crop_cols must be a multiple of 16");

  for (const MosSequence& q : data) {
    if (!(q.weight > 0.0) || !std::isfinite(q.weight))
      throw std::invalid_argument("train: the weight of " + q.dir + " must be positive");
    if (q.sensor.N_scan != sensor.N_scan || q.sensor.Horizon_SCAN != sensor.Horizon_SCAN)
      throw std::invalid_argument("train: " + q.dir + " has " + std::to_string(q.sensor.N_scan) + " x " +
                                  std::to_string(q.sensor.Horizon_SCAN) + " range images, the network " +
                                  std::to_string(sensor.N_scan) + " x " +
                                  std::to_string(sensor.Horizon_SCAN));
  }
  // Class weight: sqrt of the static / moving pixel ratio of the training split, as drawn.
  double n_moving = 0.0, n_static = 0.0;
  for (const FrameRef& r : split.train)
    for (std::uint8_t t : data[r.seq].frames[r.frame].target) {
      n_moving += data[r.seq].weight * (t == kTargetMoving);
      n_static += data[r.seq].weight * (t == kTargetStatic);
    }
  if (n_moving == 0.0) throw std::invalid_argument("train: no moving point in the training frames");
  const double pos_weight = std::sqrt(n_static / n_moving);

  MosNet net(MosNetOptions{o.m, o.width, sensor.N_scan, sensor.Horizon_SCAN});
  net->train();
  torch::optim::Adam opt(net->parameters(),
                         torch::optim::AdamOptions(o.learning_rate).weight_decay(o.weight_decay));
  std::vector<EpochReport> reports;
  std::ofstream log(o.out + ".csv");
  log << "epoch,train_loss,val_iou,val_precision,val_recall,seconds\n";
  double best_iou = -1.0;
  std::vector<FrameRef> train = split.train;
  for (int epoch = 1; epoch <= o.epochs; ++epoch) {
    const auto t0 = std::chrono::steady_clock::now();
    const double lr = o.learning_rate * (0.05 + 0.95 * 0.5 * (1.0 + std::cos(M_PI * (epoch - 1) / o.epochs)));
    for (auto& g : opt.param_groups()) static_cast<torch::optim::AdamOptions&>(g.options()).lr(lr);
    std::shuffle(train.begin(), train.end(), rng);
    const std::vector<FrameRef> order = epoch_draws(data, train, rng);
    const std::size_t steps = order.size() / static_cast<std::size_t>(o.batch);
    double loss_sum = 0.0;
    for (std::size_t step = 0; step < steps; ++step) {
      std::vector<torch::Tensor> xs, ys;
      for (int b = 0; b < o.batch; ++b) {
        const FrameRef& r = order[step * static_cast<std::size_t>(o.batch) + static_cast<std::size_t>(b)];
        const MosFrame& f = data[r.seq].frames[r.frame];
        const RangeImageBag bag = sample_bag(data[r.seq], r.frame, o.m, o.pose_noise, &rng);
        const int c0 = std::uniform_int_distribution<int>(0, std::max(0, f.image.cols - o.crop_cols))(rng);
        const int cw = std::min(o.crop_cols, f.image.cols);
        torch::Tensor x = bag_tensor(bag).slice(3, c0, c0 + cw);
        torch::Tensor y = target_tensor(f).slice(3, c0, c0 + cw);
        x.select(1, kBagIntensity).mul_(std::uniform_real_distribution<double>(0.7, 1.3)(rng));
        if (std::bernoulli_distribution(0.5)(rng)) {  // mirror the sweep: y -> -y
          x = x.flip({3});
          y = y.flip({3});
          x.select(1, kBagY).neg_();
        }
        xs.push_back(x);
        ys.push_back(y);
      }
      opt.zero_grad();
      const torch::Tensor loss = mos_loss(forward_padded(net, torch::cat(xs)), torch::cat(ys), pos_weight);
      loss.backward();
      opt.step();
      loss_sum += loss.item<double>();
      if (cb.on_step) cb.on_step(epoch, step + 1, steps, loss_sum / static_cast<double>(step + 1));
    }
    EpochReport rep;
    rep.epoch = epoch;
    rep.train_loss = steps ? loss_sum / static_cast<double>(steps) : 0.0;
    if (!split.val.empty()) {
      const PixelScore s = score(net, data, split.val, o.m);
      rep.val_iou = s.iou();
      rep.val_precision = s.tp + s.fp ? static_cast<double>(s.tp) / (s.tp + s.fp) : 0.0;
      rep.val_recall = s.tp + s.fn ? static_cast<double>(s.tp) / (s.tp + s.fn) : 0.0;
    }
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    save_mos_net(net, o.out + ".last");
    if (split.val.empty() || rep.val_iou > best_iou) {
      best_iou = rep.val_iou;
      rep.best = true;
      save_mos_net(net, o.out);
    }
    log << rep.epoch << ',' << rep.train_loss << ',' << rep.val_iou << ',' << rep.val_precision << ','
        << rep.val_recall << ',' << rep.seconds << '\n'
        << std::flush;
    reports.push_back(rep);
    if (cb.on_epoch) cb.on_epoch(rep);
  }
  return reports;
}

}  // namespace dloam::cnn
