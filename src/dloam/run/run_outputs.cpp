#include "dloam/run/run_outputs.hpp"

#include <filesystem>

#include "dloam/core/voxel_grid.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/ply.hpp"
#include "dloam/io/timing_csv.hpp"

namespace dloam::run {

namespace fs = std::filesystem;

RunOutputs::RunOutputs(OutputOptions options, const PipelineConfig& config)
    : options_(std::move(options)), degenerate_(config.sensor) {
  if (config.detection.detector == Detector::kAuto)
    throw std::invalid_argument("RunOutputs: resolve detection.detector first (run::prepare_detector)");
  labels_on_ = options_.labels && config.detection.detector != Detector::kNone;
  fs::create_directories(options_.dir);
  if (labels_on_) fs::create_directories(options_.dir + "/labels");
  io::write_atomic(options_.dir + "/config.yaml", [&](std::ostream& o) { o << io::dump_config(config); });
  if (options_.camera_Tr) {
    io::Calib calib;
    calib.Tr = *options_.camera_Tr;
    calib.has_Tr = true;
    std::vector<double> tr;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) tr.push_back(calib.Tr.matrix()(r, c));
    calib.entries.emplace_back("Tr", tr);
    io::write_calib(options_.dir + "/calib.txt", calib);
  }
}

namespace {

/// The labels of a scan one per point of its file: the points the reader dropped unlabelled.
std::vector<Label> file_labels(const std::vector<Label>& labels, const io::ScanInfo* info) {
  if (!info || info->kept.empty()) return labels;
  std::vector<Label> out(info->file_points, semantic::kUnlabeled);
  for (std::size_t j = 0; j < info->kept.size() && j < labels.size(); ++j) out[info->kept[j]] = labels[j];
  return out;
}

}  // namespace

std::string RunOutputs::add(ScanResult& r, const PointCloud& cloud, const std::vector<Label>* gt,
                            const ScanOrigin& origin) {
  const std::string name = origin.name.empty() ? io::scan_name(r.index) : origin.name;
  if (labels_on_)
    io::write_labels(options_.dir + "/labels/" + name + ".label", file_labels(r.labels, origin.info));
  const std::string warning = degenerate_.add(r, cloud, origin.info ? origin.info->dropped() : 0,
                                              origin.file.empty() ? name : origin.file);
  std::vector<Vec3> moving;
  for (std::size_t i = 0; i < r.labels.size() && i < cloud.size(); ++i)
    if (semantic::is_moving(r.labels[i])) moving.push_back(cloud.xyz[i]);
  moving_.push_back(voxel_downsample_points(moving, options_.moving_leaf_size));
  if (gt) {
    if (!label_stats_) label_stats_.emplace();
    label_stats_->add(*gt, r);
  }
  realtime_poses_.push_back(r.pose);
  // What timing.csv and the tracking summary need: the result without its per-point vectors
  // (swapped with empty ones to free the memory: = {} keeps the capacity).
  ScanResult kept = r;
  std::vector<Label>().swap(kept.labels);
  std::vector<std::size_t>().swap(kept.edge_features);
  std::vector<std::size_t>().swap(kept.plane_features);
  std::vector<std::size_t>().swap(kept.map_points);
  results_.push_back(std::move(kept));
  return warning;
}

void RunOutputs::discard() const {
  std::error_code ec;
  fs::remove(options_.dir + "/config.yaml", ec);
  if (options_.camera_Tr) fs::remove(options_.dir + "/calib.txt", ec);
  if (labels_on_ && fs::is_empty(options_.dir + "/labels", ec)) fs::remove(options_.dir + "/labels", ec);
}

std::vector<Pose> RunOutputs::in_output_frame(const std::vector<Pose>& lidar_poses) const {
  return options_.camera_Tr ? io::lidar_to_camera(lidar_poses, *options_.camera_Tr) : lidar_poses;
}

void RunOutputs::write_poses() const { write_poses(realtime_poses_); }

void RunOutputs::write_poses(const std::vector<Pose>& lidar_poses) const {
  const std::vector<Pose> poses = in_output_frame(lidar_poses);
  io::write_kitti_poses(options_.dir + "/poses.txt", poses);
  std::vector<io::StampedPose> tum;
  for (std::size_t i = 0; i < poses.size() && i < results_.size(); ++i)
    tum.push_back({results_[i].stamp, poses[i]});
  io::write_tum_poses(options_.dir + "/poses_tum.txt", tum);
}

RunSummary RunOutputs::finish(Pipeline& pipeline, const std::vector<Pose>* gt_lidar_poses) {
  RunSummary s;
  s.scans = results_.size();
  s.results = results_;
  // Mapping-refined poses (loop closures move earlier scans too); after a failure inside the
  // pipeline, the real-time poses when the refined ones cannot be had.
  s.trajectory = realtime_poses_;
  try {
    const std::vector<Pose> refined = pipeline.trajectory();
    if (refined.size() >= s.trajectory.size())
      s.trajectory.assign(refined.begin(), refined.begin() + static_cast<long>(s.trajectory.size()));
  } catch (const std::exception& e) {
    s.problems.push_back(std::string("the mapping-refined poses are unavailable (") + e.what() +
                         "): poses.txt holds the real-time poses");
  }
  write_poses(s.trajectory);
  io::write_timing_csv(options_.dir + "/timing.csv", results_);
  PointCloud map;
  try {
    map.xyz = pipeline.global_map();
  } catch (const std::exception& e) {
    s.problems.push_back(std::string("the global map is unavailable (") + e.what() + "): map.ply is empty");
  }
  s.map_points = map.size();
  io::write_ply(options_.dir + "/map.ply", map);
  PointCloud moving;
  for (std::size_t i = 0; i < moving_.size() && i < s.trajectory.size(); ++i)
    for (const Vec3& p : moving_[i]) moving.xyz.push_back(s.trajectory[i] * p);
  s.moving_points = moving.size();
  io::write_ply(options_.dir + "/moving.ply", moving);
  try {
    s.loop_closures = pipeline.loop_closures();
  } catch (const std::exception&) {  // the same failure as above
  }

  nlohmann::json& j = s.metrics;
  j = nlohmann::json::object();
  if (gt_lidar_poses && !s.trajectory.empty()) {
    if (gt_lidar_poses->size() != s.trajectory.size())
      throw std::invalid_argument("RunOutputs::finish: " + std::to_string(gt_lidar_poses->size()) +
                                  " ground-truth poses for " + std::to_string(s.trajectory.size()) +
                                  " scans");
    io::write_kitti_poses(options_.dir + "/poses_gt.txt", in_output_frame(*gt_lidar_poses));
    s.segments = segment_options(*gt_lidar_poses, options_.lengths);
    s.odometry = eval::evaluate_odometry(*gt_lidar_poses, s.trajectory, s.segments);
    j["odometry"] = odometry_json(*s.odometry, s.segments, "lidar");
  }
  if (label_stats_ && !results_.empty()) {
    s.labels = label_stats_;
    j.update(label_stats_->json());
  }
  j["tracking"] = tracking_json(results_);
  j["loop_closures"] = s.loop_closures;
  j["scans"] = degenerate_.json();
  s.degenerate = degenerate_.degenerate();
  s.without_usable_points = degenerate_.without_usable_points();
  s.dropped_points = degenerate_.dropped_points();
  s.all_degenerate_after_first = degenerate_.all_after_first();
  io::write_atomic(options_.dir + "/metrics.json", [&](std::ostream& o) { o << j.dump(2) << '\n'; });
  return s;
}

}  // namespace dloam::run
