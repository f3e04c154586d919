#include "dloam/cnn/mos_dataset.hpp"

#include "dloam/core/deskew.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/io/kitti.hpp"

namespace dloam::cnn {

namespace {

MosFrame prepare_frame(const PointCloud& cloud, const std::vector<Label>& labels, const Pose& pose,
                       const Pose& motion, const SensorConfig& sensor) {
  std::vector<Vec3> points = cloud.xyz;
  correct_vertical_angle(points, sensor.vertical_angle_correction_deg);
  points = deskew(points, point_times(cloud, true), motion);
  RangeImage full = project(points, sensor);
  MosFrame f;
  f.image.rows = full.rows;
  f.image.cols = full.cols;
  f.image.range = std::move(full.range);
  f.image.point_of_pixel.assign(f.image.range.size(), -1);
  f.target.assign(f.image.range.size(), kTargetIgnore);
  for (std::size_t px = 0; px < f.target.size(); ++px) {
    const int i = full.point_of_pixel[px];
    if (i < 0) continue;
    const auto idx = static_cast<std::size_t>(i);
    f.image.point_of_pixel[px] = static_cast<int>(f.points.size());
    f.image.row_of_point.push_back(static_cast<int>(px) / f.image.cols);
    f.image.col_of_point.push_back(static_cast<int>(px) % f.image.cols);
    f.points.push_back(points[idx]);
    f.intensity.push_back(cloud.has_intensity() ? cloud.intensity[idx] : 0.0f);
    const Label l = labels[idx];
    f.target[px] = semantic::is_ignored(l)  ? kTargetIgnore
                   : semantic::is_moving(l) ? kTargetMoving
                                            : kTargetStatic;
  }
  f.pose = pose;
  return f;
}

Pose random_perturbation(const PoseNoise& noise, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const double r = noise.rotation_deg * M_PI / 180.0;
  Vec6 xi;
  xi << n(rng) * r, n(rng) * r, n(rng) * r, n(rng) * noise.translation_m, n(rng) * noise.translation_m,
      n(rng) * noise.translation_m;  // [omega; v]
  return exp_se3(xi);
}

}  // namespace

MosSequence load_mos_sequence(const std::string& dir, const SensorConfig& sensor,
                              const std::function<void(std::size_t, std::size_t)>& progress) {
  const io::Sequence seq = io::open_sequence(dir);
  if (!seq.has_labels()) throw InputError(dir + ": no labels/ folder (training needs per-point labels)");
  if (!seq.has_poses()) throw InputError(dir + ": no poses.txt (training needs ground-truth poses)");
  const std::vector<Pose> poses = seq.lidar_poses();
  MosSequence out;
  out.dir = dir;
  out.frames.reserve(seq.size());
  for (std::size_t k = 0; k < seq.size(); ++k) {
    const PointCloud cloud = seq.read_scan(k);
    const auto labels = seq.read_scan_labels(k, cloud.size());
    const Pose motion = k > 0 ? poses[k - 1].inverse() * poses[k] : Pose::Identity();
    out.frames.push_back(prepare_frame(cloud, labels, poses[k], motion, sensor));
    if (progress) progress(k + 1, seq.size());
  }
  return out;
}

RangeImageBag sample_bag(const MosSequence& seq, std::size_t k, int m, const SensorConfig& sensor,
                         const PoseNoise& noise, std::mt19937* rng) {
  const MosFrame& f = seq.frames.at(k);
  std::vector<PastScan> past;
  for (int j = 1; j <= m && static_cast<std::size_t>(j) <= k; ++j) {
    const MosFrame& pf = seq.frames[k - static_cast<std::size_t>(j)];
    past.push_back({pf.image.range, rng ? pf.pose * random_perturbation(noise, *rng) : pf.pose});
  }
  std::vector<const PastScan*> ptrs;
  for (const PastScan& p : past) ptrs.push_back(&p);
  return make_range_image_bag(f.image, f.points, f.intensity, f.pose, ptrs, m, sensor);
}

}  // namespace dloam::cnn
