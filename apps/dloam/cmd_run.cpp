// `dloam run`: the SLAM pipeline over a sequence folder. Writes poses (KITTI + TUM), the global
// static map (PLY), per-scan per-module timing, the full config used, moving labels when a
// detector is on, and metrics when the folder has ground truth. Ctrl-C stops after the current
// scan and still writes complete outputs for the scans processed.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>

#include "commands.hpp"
#include "dloam/core/preprocess.hpp"
#include "dloam/core/range_image.hpp"
#include "dloam/eval/mos_metrics.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#ifdef DLOAM_WITH_TORCH
#include "dloam/cnn/cnn_segmenter.hpp"
#endif
#include "dloam/io/kitti.hpp"
#include "dloam/io/ply.hpp"
#include "dloam/io/sensor_estimate.hpp"
#include "dloam/io/timing_csv.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "input_args.hpp"
#include "progress.hpp"
#include "report.hpp"

namespace dloam::app {
namespace {

namespace fs = std::filesystem;
std::atomic<bool> g_stop{false};

struct RunArgs {
  std::string sequence, out, config_path, preset, detector, deskew, platform;
  InputArgs input;
  std::vector<double> lengths;
  long first = 0, count = -1;
  bool drop_moving = false;
};

/// The preset is the starting point; the file's keys override it (as `dloam config dump`). A
/// sensor preset auto stays unresolved until `estimated` is given.
PipelineConfig make_config(const RunArgs& a, const SensorConfig* estimated = nullptr) {
  PipelineConfig cfg = estimated ? io::config_from(a.preset, a.config_path, *estimated)
                                 : io::config_from_allowing_auto(a.preset, a.config_path);
  if (!a.detector.empty()) cfg.detection.detector = a.detector;
  if (a.deskew == "on") cfg.deskew.enabled = true;
  if (a.deskew == "off") cfg.deskew.enabled = false;
  if (!a.platform.empty()) cfg.motion = motion_preset(a.platform);
  io::validate_config(cfg, a.config_path.empty() ? "built-in config" : a.config_path);
  return cfg;
}

/// A scan whose points mostly miss the sensor model's vertical field of view means the wrong
/// sensor model (beam count / angles): stop with a clear message instead of a useless run.
void check_sensor_fits(const PointCloud& cloud, const SensorConfig& sensor, const std::string& file) {
  std::size_t inside = 0, in_range = 0;
  std::vector<Vec3> points = cloud.xyz;
  correct_vertical_angle(points, sensor.vertical_angle_correction_deg);
  const BeamLookup beams(sensor);  // the rows of the range image, beam origin heights included
  for (const auto& p : points) {
    const double r = p.norm();
    if (r < sensor.min_range || r > sensor.max_range) continue;
    ++in_range;
    inside += beams.row(p) >= 0;
  }
  if (in_range > 0 && inside < 0.9 * static_cast<double>(in_range)) {
    throw InputError(fmt::format(
        "{}: only {:.0f}% of the points lie inside the vertical field of view of the sensor model '{}' "
        "({} beams, {:.1f} .. {:.1f} deg): wrong --preset or sensor config? (`dloam check` estimates it)",
        file, 100.0 * inside / in_range, sensor.preset, sensor.N_scan, sensor.beam_elevation_deg(0),
        sensor.beam_elevation_deg(sensor.N_scan - 1)));
  }
}

/// Ground-truth label statistics of a run (sequence with labels/): Table III's effective-feature
/// ratio, and the fraction of the points added to the global map (before its voxel downsampling)
/// that the ground truth labels moving (ghost points).
struct LabelStats {
  eval::FeatureCounts features;
  std::uint64_t map_points = 0, map_moving = 0;
  void add(const std::vector<Label>& gt, const ScanResult& r) {
    std::vector<std::size_t> idx = r.edge_features;
    idx.insert(idx.end(), r.plane_features.begin(), r.plane_features.end());
    features += eval::count_effective_features(gt, idx);
    for (std::size_t i : r.map_points) {
      if (semantic::is_ignored(gt[i])) continue;
      ++map_points;
      map_moving += semantic::is_moving(gt[i]);
    }
  }
  void write(const std::string& path) const {
    nlohmann::json j = nlohmann::json::object();
    if (fs::exists(path)) j = nlohmann::json::parse(std::ifstream(path));
    j["effective_feature_ratio"] = features.ratio();
    j["features_on_labelled_points"] = features.total;
    j["map_input_moving_fraction"] = map_points ? static_cast<double>(map_moving) / map_points : 0.0;
    io::write_atomic(path, [&](std::ostream& o) { o << j.dump(2) << '\n'; });
    fmt::print("effective features (Table III): {:.2f} % of {}; moving points sent to the map: {:.3f} %\n",
               100.0 * features.ratio(), features.total, map_points ? 100.0 * map_moving / map_points : 0.0);
  }
};

/// The scan without the points the ground truth labels moving (--drop-labelled-moving): what a
/// perfect detector would leave. `kept`: input index of each remaining point.
PointCloud without_moving(const PointCloud& cloud, const std::vector<Label>& gt,
                          std::vector<std::size_t>& kept) {
  PointCloud out;
  kept.clear();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (semantic::is_moving(gt[i])) continue;
    kept.push_back(i);
    out.xyz.push_back(cloud.xyz[i]);
    if (cloud.has_intensity()) out.intensity.push_back(cloud.intensity[i]);
    if (cloud.has_time()) out.time.push_back(cloud.time[i]);
  }
  return out;
}

/// A result of the reduced scan in the input's point indices; the dropped points are moving.
void restore_indices(ScanResult& r, const std::vector<std::size_t>& kept, std::size_t input_size) {
  for (auto* idx : {&r.edge_features, &r.plane_features, &r.map_points})
    for (std::size_t& i : *idx) i = kept[i];
  if (r.labels.empty()) return;
  std::vector<Label> labels(input_size, semantic::kMovingGeneric);
  for (std::size_t j = 0; j < kept.size(); ++j) labels[kept[j]] = r.labels[j];
  r.labels = std::move(labels);
}

void write_trajectories(const std::string& dir, const io::Sequence& seq,
                        const std::vector<ScanResult>& results, const std::vector<Pose>& lidar_poses) {
  // Same frame convention as the input's poses.txt: camera frame when calib.txt has Tr.
  const bool camera = seq.calib && seq.calib->has_Tr;
  const auto poses = camera ? io::lidar_to_camera(lidar_poses, seq.calib->Tr) : lidar_poses;
  io::write_kitti_poses(dir + "/poses.txt", poses);
  std::vector<io::StampedPose> tum;
  for (std::size_t i = 0; i < poses.size(); ++i) tum.push_back({results[i].stamp, poses[i]});
  io::write_tum_poses(dir + "/poses_tum.txt", tum);
}

void print_summary(const std::vector<ScanResult>& results) {
  ModuleTimes mean;
  for (const auto& r : results)
    for (std::size_t m = 0; m < mean.ms.size(); ++m) mean.ms[m] += r.times.ms[m] / results.size();
  fmt::print("\nper-scan time (ms, mean over {} scans):\n", results.size());
  for (std::size_t m = 0; m < mean.ms.size(); ++m)
    fmt::print("  {:<13} {:8.2f}\n", kModuleNames[m], mean.ms[m]);
  fmt::print("  => {:.1f} scans/s\n", mean[Module::kTotal] > 0 ? 1000.0 / mean[Module::kTotal] : 0.0);
}

/// How the tracking went: scans lost before the scans of the run (gaps in the stamps), steps the
/// odometry re-initialised or could not estimate, degenerate scans.
nlohmann::json tracking_json(const std::vector<ScanResult>& results) {
  std::size_t gaps = 0, missed = 0, degenerate = 0, searched = 0, reinitialized = 0;
  std::vector<std::size_t> lost;
  double max_dt = 0.0;
  for (const ScanResult& r : results) {
    gaps += r.missed_scans > 0;
    missed += static_cast<std::size_t>(r.missed_scans);
    degenerate += r.degenerate;
    searched += r.search_candidates > 0;
    reinitialized += r.reinitialized;
    if (r.lost) lost.push_back(r.index);
    max_dt = std::max(max_dt, r.dt);
  }
  return {{"scans", results.size()},       {"gaps", gaps},
          {"missed_scans", missed},        {"max_interval_s", max_dt},
          {"searched_steps", searched},    {"reinitialized_steps", reinitialized},
          {"lost_steps", lost.size()},     {"lost_scans", lost},
          {"degenerate_scans", degenerate}};
}

void print_tracking(const std::vector<ScanResult>& results) {
  const nlohmann::json t = tracking_json(results);
  if (t["gaps"].get<std::size_t>() > 0)
    fmt::print("gaps in the scan times: {} ({} scans missing, longest interval {:.3f} s)\n",
               t["gaps"].get<std::size_t>(), t["missed_scans"].get<std::size_t>(),
               t["max_interval_s"].get<double>());
  if (t["reinitialized_steps"].get<std::size_t>() > 0)
    fmt::print("steps re-initialised by a search (the prediction did not fit): {}\n",
               t["reinitialized_steps"].get<std::size_t>());
  if (t["lost_steps"].get<std::size_t>() > 0)
    fmt::print("steps that could not be estimated (listed in metrics.json): {}\n",
               t["lost_steps"].get<std::size_t>());
  if (t["degenerate_scans"].get<std::size_t>() > 0)
    fmt::print("degenerate scans: {}\n", t["degenerate_scans"].get<std::size_t>());
}

/// Adds the tracking figures to metrics.json (created when the run has no ground truth).
void merge_tracking_summary(const std::string& path, const std::vector<ScanResult>& results) {
  nlohmann::json j = nlohmann::json::object();
  if (fs::exists(path)) j = nlohmann::json::parse(std::ifstream(path));
  j["tracking"] = tracking_json(results);
  io::write_atomic(path, [&](std::ostream& o) { o << j.dump(2) << '\n'; });
}

/// Resolves detector "auto" / the shipped model in `cfg` and loads the CNN when it is used.
std::shared_ptr<MovingSegmenter> prepare_detector(PipelineConfig& cfg) {
#ifdef DLOAM_WITH_TORCH
  std::string note;
  auto segmenter = cnn::prepare_detector(cfg.detection, DLOAM_MODEL_DIR, cfg.sensor, &note);
  if (!note.empty()) fmt::print(stderr, "{}\n", note);
  return segmenter;
#else
  if (cfg.detection.detector == "auto") cfg.detection.detector = "geometric";
  if (cfg.detection.detector == "cnn")
    throw std::invalid_argument("detector cnn: this dloam was built without LibTorch (DLOAM_WITH_TORCH=OFF)");
  return nullptr;
#endif
}

/// Sensor preset auto: the model estimated from 10 scans spread over the first 100 of the run
/// (the file's explicit sensor keys still override it).
PipelineConfig estimate_sensor(const RunArgs& a, const PipelineConfig& cfg, const io::Sequence& seq,
                               std::size_t first, std::size_t last) {
  const auto indices = io::spread_scan_indices(first, std::min(last, first + 100), 10);
  SensorEstimationConfig estimation;
  estimation.vertical_angle_correction_deg = cfg.sensor.vertical_angle_correction_deg;
  const SensorModelEstimate est = io::estimate_sequence_sensor(seq, indices, estimation);
  fmt::print("sensor auto: estimated from scans {} .. {}:\n", indices.front(), indices.back());
  for (const auto& line : io::describe_estimate(est)) fmt::print("  {}\n", line);
  PipelineConfig out = make_config(a, &est.sensor);
  out.input = cfg.input;
  return out;
}

/// The sensor model of a raw-packet recording replaces the default one when neither --preset nor
/// the config file's sensor section chose one.
void take_recording_sensor(PipelineConfig& cfg, const io::Sequence& seq, const RunArgs& a) {
  if (!seq.sensor || !a.preset.empty() || io::config_file_sets(a.config_path, "sensor")) return;
  cfg.sensor = *seq.sensor;
  io::validate_config(cfg, "the sensor model of " + a.sequence);
  fmt::print("sensor model from the recording: {} ({} beams, {} columns, {:.1f} Hz, {:.1f} .. {:.1f} m)\n",
             cfg.sensor.preset, cfg.sensor.N_scan, cfg.sensor.Horizon_SCAN, cfg.sensor.scan_rate_hz,
             cfg.sensor.min_range, cfg.sensor.max_range);
}

void run(const RunArgs& a) {
  PipelineConfig cfg = make_config(a);
  cfg.input = apply_input_args(cfg.input, a.input);
  const io::Sequence seq = io::open_sequence(a.sequence, to_input_options(cfg.input));
  take_recording_sensor(cfg, seq, a);
  const std::size_t first = static_cast<std::size_t>(std::max(0L, a.first));
  if (first >= seq.size())
    throw InputError(
        fmt::format("{}: --first {} but the sequence has {} scans", a.sequence, first, seq.size()));
  if (a.drop_moving && !seq.has_labels())
    throw InputError(a.sequence + ": --drop-labelled-moving needs ground-truth labels (labels/*.label)");
  const std::size_t last =
      a.count < 0 ? seq.size() : std::min(seq.size(), first + static_cast<std::size_t>(a.count));
  if (io::sensor_needs_estimate(cfg)) cfg = estimate_sensor(a, cfg, seq, first, last);
  const std::shared_ptr<MovingSegmenter> cnn = prepare_detector(cfg);
  fs::create_directories(a.out);
  io::write_atomic(a.out + "/config.yaml", [&](std::ostream& o) { o << io::dump_config(cfg); });
  const bool labels_on = cfg.detection.detector != "none";
  if (labels_on) fs::create_directories(a.out + "/labels");

  fmt::print("dloam run: {} scans of {} ({} preset, detector {}, de-skew {}) -> {}\n", last - first,
             a.sequence, cfg.sensor.preset, cfg.detection.detector, cfg.deskew.enabled ? "on" : "off", a.out);
  Pipeline pipeline(cfg, cnn);
  std::vector<ScanResult> results;
  std::vector<Pose> poses;
  Progress progress("run", last - first);
  LabelStats label_stats;
  g_stop = false;
  auto previous_handler = std::signal(SIGINT, [](int) { g_stop = true; });
  for (std::size_t i = first; i < last && !g_stop; ++i) {
    const PointCloud cloud = seq.read_scan(i);
    if (i == first) check_sensor_fits(cloud, cfg.sensor, seq.scan_files[i]);
    const std::vector<Label> gt =
        seq.has_labels() ? seq.read_scan_labels(i, cloud.size()) : std::vector<Label>{};
    std::vector<std::size_t> kept;
    ScanResult r = pipeline.process(a.drop_moving ? without_moving(cloud, gt, kept) : cloud);
    if (a.drop_moving) restore_indices(r, kept, cloud.size());
    r.index = i;
    if (seq.has_labels()) label_stats.add(gt, r);
    if (labels_on) io::write_labels(fmt::format("{}/labels/{}.label", a.out, io::scan_name(i)), r.labels);
    poses.push_back(r.pose);
    r.labels = {};  // keep only what timing.csv needs
    r.n_edges = r.edge_features.size();
    r.n_planes = r.plane_features.size();
    r.edge_features = {};
    r.plane_features = {};
    r.map_points = {};
    results.push_back(std::move(r));
    if (results.size() % 50 == 0)
      write_trajectories(a.out, seq, results, poses);  // an interrupted run keeps its poses
    progress.update(results.size(), fmt::format("{:.0f} ms/scan", results.back().times[Module::kTotal]));
  }
  std::signal(SIGINT, previous_handler);
  if (g_stop)
    fmt::print(stderr, "\ninterrupted: writing outputs for the {} scans processed\n", results.size());

  poses = pipeline.trajectory();  // mapping-refined, loop closures move earlier scans too
  write_trajectories(a.out, seq, results, poses);
  io::write_timing_csv(a.out + "/timing.csv", results);
  PointCloud map;
  map.xyz = pipeline.global_map();
  io::write_ply(a.out + "/map.ply", map);
  print_summary(results);
  print_tracking(results);
  fmt::print("loop closures: {}\n", pipeline.loop_closures());
  if (seq.source) fmt::print("input: {}\n", seq.source->describe());
  fmt::print("wrote {}/poses.txt, poses_tum.txt, map.ply ({} points), timing.csv, config.yaml{}\n", a.out,
             map.size(), labels_on ? ", labels/" : "");

  if (seq.has_poses()) {
    const auto gt_all = seq.lidar_poses();
    const std::vector<Pose> gt(gt_all.begin() + static_cast<long>(first),
                               gt_all.begin() + static_cast<long>(first + poses.size()));
    write_odometry_metrics(a.out + "/metrics.json", gt, poses, a.lengths);
  }
  if (seq.has_labels() && !results.empty()) label_stats.write(a.out + "/metrics.json");
  merge_tracking_summary(a.out + "/metrics.json", results);
  if (g_stop) throw InputError("interrupted by the user (outputs written)");
}

}  // namespace

void register_run(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "Run the SLAM pipeline on a sequence folder");
  cmd->footer(
      "Input: a KITTI / SemanticKITTI sequence folder (velodyne/*.bin, optional labels/, poses.txt,\n"
      "calib.txt, times.txt), a folder of PCD files, a ROS 1 bag of sensor_msgs/PointCloud2, a ROS 2 bag\n"
      "(rosbag2 folder, .db3, .mcap) of PointCloud2 or raw packets, or a pcap / pcapng capture. Raw\n"
      "packets (Velodyne, Ouster, Hesai) give the sensor model unless --preset or the config's sensor:\n"
      "section sets one.\n"
      "Outputs in --out: poses.txt (KITTI, camera frame when calib.txt has Tr), poses_tum.txt, map.ply,\n"
      "timing.csv (ms per scan and module), config.yaml (the full config used), labels/ (detector on),\n"
      "metrics.json (when the folder has poses.txt).\n"
      "Examples:\n"
      "  dloam run ../shared/data/kitti-raw-0005 --out out/0005 --config config/kitti-raw.yaml\n"
      "  dloam run sim/urban --out out/urban --preset HDL-64E --detector none\n"
      "  dloam run my_vlp16_pcds --out out/mine --preset VLP-16 --first 100 --count 500\n"
      "  dloam run drive.bag --topic /velodyne_points --out out/drive --preset VLP-16\n"
      "  dloam run my_pcds --out out/mine --preset auto      # sensor model estimated from the first scans\n"
      "  dloam run vlp16.pcap --out out/vlp16\n"
      "  dloam run os1.pcap --metadata os1.json --returns strongest --out out/os1\n"
      "  dloam run drive_bag/ --topic /points --out out/drive   # rosbag2 folder (.db3 or .mcap inside)");
  cmd->add_option("SEQUENCE_DIR", args->sequence,
                  "sequence folder, bag (.bag, .db3, .mcap, rosbag2 folder) or capture (.pcap, .pcapng)")
      ->required()
      ->check(CLI::ExistingPath);
  add_input_options(cmd, args->input);
  cmd->add_option("--out,-o", args->out, "output folder")->required();
  cmd->add_option("--config,-c", args->config_path, "YAML config (see `dloam config dump`)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--preset", args->preset,
                  "sensor preset: " + sensor_preset_list() +
                      "; or auto: estimated from the first scans (see `dloam check --write-sensor`)");
  cmd->add_option("--detector", args->detector, "dynamic-object detector: none, geometric or cnn")
      ->check(CLI::IsMember({"none", "geometric", "cnn"}));
  cmd->add_flag(
      "--drop-labelled-moving", args->drop_moving,
      "delete the points labels/ marks moving before the pipeline sees them: a perfect "
      "detector's reference for studies (use with --detector none); written labels mark them moving");
  cmd->add_option("--deskew", args->deskew, "override the config's de-skew switch")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option(
         "--platform", args->platform,
         "motion limits of the platform (the config's motion section): car (default), handheld, legged")
      ->check(CLI::IsMember(motion_platform_names()));
  cmd->add_option("--lengths", args->lengths,
                  "segment lengths (m) for metrics.json; default: devkit 100..800, "
                  "or 5,10,20,30 with every frame as a start on drives under 200 m")
      ->delimiter(',');
  cmd->add_option("--first", args->first, "first scan index");
  cmd->add_option("--count", args->count, "number of scans (default: all)");
  cmd->callback([args] { run(*args); });
}

}  // namespace dloam::app
