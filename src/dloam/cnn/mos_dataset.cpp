#include "dloam/cnn/mos_dataset.hpp"

#include <cmath>
#include <filesystem>

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

MosSource parse_mos_source(const std::string& spec) {
  MosSource s;
  std::size_t pos = spec.find(',');
  s.dir = spec.substr(0, pos);
  if (s.dir.empty()) throw InputError("training source '" + spec + "': no folder before the options");
  while (pos != std::string::npos) {
    const std::size_t next = spec.find(',', pos + 1);
    const std::string item =
        spec.substr(pos + 1, next == std::string::npos ? std::string::npos : next - pos - 1);
    pos = next;
    const std::size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    const std::string value = eq == std::string::npos ? std::string() : item.substr(eq + 1);
    if (value.empty())
      throw InputError("training source '" + spec + "': '" + item +
                       "' is not KEY=VALUE (run=DIR, weight=W, config=FILE)");
    if (key == "run") {
      s.run_dir = value;
    } else if (key == "config") {
      s.config = value;
    } else if (key == "weight") {
      std::size_t used = 0;
      double w = 0.0;
      try {
        w = std::stod(value, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != value.size() || !std::isfinite(w) || w <= 0.0 || w > 1000.0)
        throw InputError("training source '" + spec + "': weight '" + value +
                         "' is not a number in (0, 1000]");
      s.weight = w;
    } else {
      throw InputError("training source '" + spec + "': unknown key '" + key +
                       "' (run=DIR, weight=W, config=FILE)");
    }
  }
  return s;
}

MosSequence load_mos_sequence(const std::string& dir, const SensorConfig& sensor,
                              const std::function<void(std::size_t, std::size_t)>& progress) {
  return load_mos_sequence(MosSource{dir, {}, 1.0, {}}, sensor, progress);
}

MosSequence load_mos_sequence(const MosSource& source, const SensorConfig& sensor,
                              const std::function<void(std::size_t, std::size_t)>& progress) {
  const std::string& dir = source.dir;
  io::Sequence seq = io::open_sequence(dir);
  if (!source.run_dir.empty()) {
    // Labels of the whole-drive pass and the run's own poses replace whatever the folder holds
    // (an annotated drive's labels/ must not leak into training on it).
    namespace fs = std::filesystem;
    const fs::path run(source.run_dir);
    const fs::path poses_file = run / "poses.txt";
    if (!fs::is_regular_file(poses_file))
      throw InputError(poses_file.string() + ": missing (run=" + source.run_dir +
                       " must be a `dloam run` output folder)");
    seq.poses = io::read_kitti_poses(poses_file.string());
    if (seq.poses.size() != seq.size())
      throw InputError(poses_file.string() + ": has " + std::to_string(seq.poses.size()) + " poses but " +
                       dir + " has " + std::to_string(seq.size()) +
                       " scans (was the run made on this sequence?)");
    seq.calib.reset();
    if (fs::is_regular_file(run / "calib.txt")) seq.calib = io::read_calib((run / "calib.txt").string());
    seq.label_files.clear();
    for (std::size_t k = 0; k < seq.size(); ++k) {
      const fs::path label = run / "clean" / "labels" / (seq.output_name(k) + ".label");
      if (!fs::is_regular_file(label))
        throw InputError(label.string() + ": missing (run `dloam clean " + dir + " " + source.run_dir +
                         "` first)");
      seq.label_files.push_back(label.string());
    }
  }
  if (!seq.has_labels()) throw InputError(dir + ": no labels/ folder (training needs per-point labels)");
  if (!seq.has_poses()) throw InputError(dir + ": no poses.txt (training needs ground-truth poses)");
  const std::vector<Pose> poses = seq.lidar_poses();
  MosSequence out;
  out.dir = dir;
  out.weight = source.weight;
  out.sensor = sensor;
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

RangeImageBag sample_bag(const MosSequence& seq, std::size_t k, int m, const PoseNoise& noise,
                         std::mt19937* rng) {
  const MosFrame& f = seq.frames.at(k);
  std::vector<PastScan> past;
  for (int j = 1; j <= m && static_cast<std::size_t>(j) <= k; ++j) {
    const MosFrame& pf = seq.frames[k - static_cast<std::size_t>(j)];
    past.push_back({pf.image.range, rng ? pf.pose * random_perturbation(noise, *rng) : pf.pose});
  }
  std::vector<const PastScan*> ptrs;
  for (const PastScan& p : past) ptrs.push_back(&p);
  return make_range_image_bag(f.image, f.points, f.intensity, f.pose, ptrs, m, seq.sensor);
}

}  // namespace dloam::cnn
