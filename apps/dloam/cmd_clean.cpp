// `dloam clean SEQUENCE RUN_DIR`: after `dloam run`, the whole-drive pass over every scan with the
// run's poses: moving labels decided from the views before and after each scan, and the static
// map without the places seen empty at another time. Writes RUN_DIR/clean/.
#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "clean_pass.hpp"
#include "commands.hpp"
#include "dloam/core/deskew.hpp"
#include "dloam/core/map_cleaner.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/eval/mos_metrics.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/input_options.hpp"
#include "dloam/io/pcd.hpp"
#include "dloam/io/ply.hpp"
#include "dloam/run/metrics.hpp"
#include "input_args.hpp"
#include "odometry_table.hpp"
#include "progress.hpp"

namespace dloam::app {

namespace fs = std::filesystem;

std::vector<Pose> read_run_poses(const std::string& run_dir, const io::Sequence& seq) {
  const std::string path = run_dir + "/poses.txt";
  if (!fs::exists(path))
    throw InputError(path + ": missing (RUN_DIR must be the --out folder of `dloam run`)");
  std::vector<Pose> poses = io::read_kitti_poses(path);
  if (poses.empty()) throw InputError(path + ": no poses");
  if (seq.calib && seq.calib->has_Tr) poses = io::camera_to_lidar(poses, seq.calib->Tr);
  return poses;
}

std::vector<Vec3> drive_scan_points(const PointCloud& cloud, const std::vector<Pose>& poses, std::size_t k,
                                    const std::vector<double>& stamps, const PipelineConfig& cfg) {
  std::vector<Vec3> points = cloud.xyz;
  correct_vertical_angle(points, cfg.sensor.vertical_angle_correction_deg);
  if (!cfg.deskew.enabled || cfg.deskew.time_source == TimeSource::kNone || poses.size() < 2) return points;
  const std::size_t a = k > 0 ? k - 1 : 0, b = k > 0 ? k : 1;
  ScanInterval interval;
  interval.sweep = 1.0 / cfg.sensor.scan_rate_hz;
  interval.dt =
      stamps.size() == poses.size() && stamps[b] > stamps[a] ? stamps[b] - stamps[a] : interval.sweep;
  const Pose step = poses[a].inverse() * poses[b];
  return deskew(points, point_times(cloud, cfg.deskew.time_source == TimeSource::kAuto),
                interval.sweep_motion(step));
}

namespace {

/// The scan as the pipeline saw it, segmented.
CleanerScan prepare(const PointCloud& cloud, const std::vector<Pose>& poses, std::size_t k,
                    const std::vector<double>& stamps, const PipelineConfig& cfg) {
  std::vector<Vec3> points = drive_scan_points(cloud, poses, k, stamps, cfg);
  const SegmentationResult seg = segment(points, cfg.sensor, cfg.segmentation);
  return make_cleaner_scan(std::move(points), seg, poses[k]);
}

}  // namespace

void clean_sequence(const io::Sequence& seq, const std::vector<Pose>& poses, std::size_t first,
                    const PipelineConfig& cfg, const std::string& out_dir) {
  if (first + poses.size() > seq.size())
    throw InputError(fmt::format("{}: {} poses from scan {} but the sequence has {} scans", seq.dir,
                                 poses.size(), first, seq.size()));
  fs::create_directories(out_dir + "/labels");
  std::vector<double> stamps;
  if (seq.times.size() == seq.size())
    stamps.assign(seq.times.begin() + static_cast<long>(first),
                  seq.times.begin() + static_cast<long>(first + poses.size()));

  MapCleaner cleaner(cfg.sensor, cfg.clean);
  CountedVoxelMap map(cfg.clean.map_leaf_size);
  eval::MosResult mos;
  std::size_t points = 0, moving = 0, moving_clusters = 0, ghost_clusters = 0, held = 0;
  Progress progress("clean", poses.size());
  std::size_t done = 0;
  auto drain = [&] {
    while (cleaner.ready()) {
      const CleanedScan s = cleaner.pop();
      const std::size_t i = first + s.index;
      io::write_labels(fmt::format("{}/labels/{}.label", out_dir, io::scan_name(i)), s.labels);
      for (std::size_t k = 0; k < s.points.size(); ++k) {
        moving += s.labels[k] == semantic::kMovingGeneric;
        if (s.in_map[k] && s.points[k].norm() <= cfg.clean.map_max_range &&
            s.points[k].norm() >= cfg.sensor.min_range)
          map.add(s.pose * s.points[k]);
      }
      points += s.points.size();
      moving_clusters += s.moving_clusters;
      ghost_clusters += s.ghost_clusters;
      if (seq.has_labels()) eval::add_scan(mos, seq.read_scan_labels(i, s.labels.size()), s.labels);
      progress.update(++done, fmt::format("{} scans held", cleaner.held()));
    }
  };
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const PointCloud cloud = seq.read_scan(first + k);
    cleaner.add(prepare(cloud, poses, k, stamps, cfg));
    held = std::max(held, cleaner.held());
    drain();
  }
  cleaner.finish();
  drain();

  PointCloud cloud;
  std::vector<std::uint32_t> counts;
  map.extract(cloud.xyz, counts);
  const std::vector<float> count_f(counts.begin(), counts.end());
  io::write_ply(out_dir + "/map.ply", cloud, io::Encoding::kBinary, {}, count_f, "count");
  cloud.time = count_f;  // the PCD's extra field, named "count"
  io::write_pcd(out_dir + "/map.pcd", cloud, io::Encoding::kBinary, "count");

  fmt::print(
      "dloam clean: {} scans, {} points: {} moving ({:.2f} %), {} moving clusters, {} more kept out of the "
      "map\n",
      poses.size(), points, moving, points ? 100.0 * moving / points : 0.0, moving_clusters, ghost_clusters);
  fmt::print("static map: {} voxels of {:g} m (points within {:g} m of their scan); at most {} scans held\n",
             cloud.size(), cfg.clean.map_leaf_size, cfg.clean.map_max_range, held);
  nlohmann::json j = {{"scans", poses.size()},
                      {"points", points},
                      {"moving_points", moving},
                      {"moving_clusters", moving_clusters},
                      {"ghost_clusters", ghost_clusters},
                      {"map_points", cloud.size()},
                      {"max_scans_held", held}};
  if (seq.has_labels()) {
    print_mos(mos, 0.5);
    j["mos"] = run::mos_json(mos, 0.5);
  }
  io::write_atomic(out_dir + "/metrics.json", [&](std::ostream& o) { o << j.dump(2) << '\n'; });
  fmt::print("wrote {}/labels/, map.ply, map.pcd, metrics.json\n", out_dir);
}

namespace {

struct CleanArgs {
  std::string sequence, run_dir, config_path;
  InputArgs input;
  long first = 0;
};

void run_clean(const CleanArgs& a) {
  // The run's own config (config.yaml of RUN_DIR) unless a file is given.
  std::string config_path = a.config_path;
  if (config_path.empty() && fs::exists(a.run_dir + "/config.yaml")) config_path = a.run_dir + "/config.yaml";
  PipelineConfig cfg = io::config_from("", config_path);
  cfg.input = apply_input_args(cfg.input, a.input);
  const io::Sequence seq = io::open_sequence(a.sequence, io::input_options(cfg.input));
  if (seq.sensor && !io::config_file_sets(config_path, "sensor")) cfg.sensor = *seq.sensor;
  const std::vector<Pose> poses = read_run_poses(a.run_dir, seq);
  fmt::print("dloam clean: {} scans of {} with the poses of {} ({}) -> {}/clean\n", poses.size(), a.sequence,
             a.run_dir, config_path.empty() ? "built-in config" : config_path, a.run_dir);
  clean_sequence(seq, poses, static_cast<std::size_t>(std::max(0L, a.first)), cfg, a.run_dir + "/clean");
}

}  // namespace

void register_clean(CLI::App& app) {
  auto args = std::make_shared<CleanArgs>();
  auto* cmd = app.add_subcommand(
      "clean", "Whole-drive pass after `dloam run`: moving labels and a static map from every scan's views");
  cmd->footer(
      "Reads the scans of SEQUENCE and RUN_DIR/poses.txt (and RUN_DIR/config.yaml unless --config is "
      "given).\n"
      "Writes RUN_DIR/clean/: labels/NNNNNN.label (9 static, 251 moving, input point order), map.ply and\n"
      "map.pcd (static map, voxel means with a per-point `count` of observations), metrics.json (MOS IoU\n"
      "as `dloam eval mos` when SEQUENCE has labels/). Parameters: the config's clean: section\n"
      "(`dloam config dump`).\n"
      "Examples:\n"
      "  dloam run ../shared/data/kitti-raw-0005 --config config/kitti-raw.yaml --out out/0005\n"
      "  dloam clean ../shared/data/kitti-raw-0005 out/0005\n"
      "  dloam eval map out/0005/clean/map.ply ../shared/data/kitti-raw-0005 out/0005/poses.txt");
  cmd->add_option("SEQUENCE", args->sequence, "the sequence the run read")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("RUN_DIR", args->run_dir, "the --out folder of `dloam run`")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--config,-c", args->config_path, "YAML config (default: RUN_DIR/config.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--first", args->first, "first scan index of the run (its --first)");
  add_input_options(cmd, args->input);
  cmd->callback([args] { run_clean(*args); });
}

}  // namespace dloam::app
