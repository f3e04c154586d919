// `dloam run`: the SLAM pipeline over a sequence folder. Writes poses (KITTI + TUM), the global
// static map (PLY), per-scan per-module timing, the full config used, moving labels when a
// detector is on, and metrics (degenerate scans; errors when the folder has ground truth). SIGINT,
// SIGTERM and SIGHUP stop after the current scan, and an error in a scan stops the run there: the
// outputs of the scans processed are written complete either way.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <filesystem>

#include "clean_pass.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "config_args.hpp"
#include "dloam/eval/mos_metrics.hpp"
#include "dloam/eval/odometry_metrics.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/input_options.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/ply.hpp"
#include "dloam/io/sensor_estimate.hpp"
#include "dloam/io/timing_csv.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "dloam/run/detector_setup.hpp"
#include "dloam/run/metrics.hpp"
#include "dloam/run/run_sequence.hpp"
#include "enum_option.hpp"
#include "html_report.hpp"
#include "input_args.hpp"
#include "odometry_table.hpp"
#include "output_dir.hpp"
#include "progress.hpp"
#include "stop_signals.hpp"

namespace dloam::app {
namespace {

namespace fs = std::filesystem;

struct RunArgs {
  std::string sequence, out, detector, deskew, platform, gt_frame = "auto";
  ConfigArgs config;
  InputArgs input;
  std::vector<double> lengths;
  long first = 0, count = -1;
  bool drop_moving = false, overwrite = false, report = false;
  bool clean = false;
};

/// The preset is the starting point; the file's keys override it (as `dloam config dump`). A
/// sensor preset auto stays unresolved until `estimated` is given.
PipelineConfig make_config(const RunArgs& a, const SensorConfig* estimated = nullptr) {
  const ConfigArgs& c = a.config;
  PipelineConfig cfg = estimated ? io::config_from(c.preset, c.config_path, *estimated)
                                 : io::config_from_allowing_auto(c.preset, c.config_path);
  if (!a.detector.empty()) cfg.detection.detector = *enum_from_name<Detector>(a.detector);  // parser-checked
  if (a.deskew == "on") cfg.deskew.enabled = true;
  if (a.deskew == "off") cfg.deskew.enabled = false;
  if (!a.platform.empty()) cfg.motion = motion_preset(a.platform);
  io::validate_config(cfg, c.config_path.empty() ? "built-in config" : c.config_path);
  return cfg;
}

/// metrics.json as written so far by this run (an empty object before).
nlohmann::json read_metrics(const std::string& path) {
  if (!fs::exists(path)) return nlohmann::json::object();
  return nlohmann::json::parse(io::read_file(path, io::kMaxConfigFileBytes));
}

/// The ground-truth label statistics into metrics.json (Table III's effective features, the moving
/// share of the points sent to the map, MOS when a detector wrote labels), and on the terminal.
void write_label_stats(const run::LabelStats& stats, const std::string& path) {
  nlohmann::json j = read_metrics(path);
  j.update(stats.json());
  io::write_atomic(path, [&](std::ostream& o) { o << j.dump(2) << '\n'; });
  fmt::print(
      "effective features (Table III): {}; moving points sent to the map: {}\n",
      stats.features.total
          ? fmt::format("{:.2f} % of {}", 100.0 * stats.features.ratio(), stats.features.total)
          : "none on labelled points",
      stats.map_points ? fmt::format("{:.3f} %", 100.0 * stats.map_moving_fraction()) : "no point sent");
  if (stats.detector) print_mos(stats.mos);
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

void print_tracking(const std::vector<ScanResult>& results) {
  const nlohmann::json t = run::tracking_json(results);
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
  j["tracking"] = run::tracking_json(results);
  io::write_atomic(path, [&](std::ostream& o) { o << j.dump(2) << '\n'; });
}

/// The odometry against the ground truth: printed, and metrics.json started with it.
void write_odometry_metrics(const std::string& json_path, const std::vector<Pose>& gt,
                            const std::vector<Pose>& est, const std::vector<double>& lengths) {
  const auto options = run::segment_options(gt, lengths);
  const auto r = eval::evaluate_odometry(gt, est, options);
  const std::string frame = "lidar";
  print_odometry(r, frame);
  const nlohmann::json doc = {{"odometry", run::odometry_json(r, options, frame)}};
  io::write_atomic(json_path, [&](std::ostream& o) { o << doc.dump(2) << '\n'; });
}

/// Scans on which the odometry had nothing to hold on to: the predicted motion was kept there.
struct DegenerateScans {
  static constexpr std::size_t kMinFeatures = 10;  ///< per kind (edges, planes), as registration's minimum
  static constexpr std::size_t kListed = 5;        ///< scans named on the screen; metrics.json lists all
  std::vector<std::size_t> scans;
  std::size_t later = 0;  ///< degenerate scans after the first of the run
  std::size_t without_points = 0, dropped_points = 0, processed = 0;

  /// Points of the cloud the sensor model keeps (within [min_range, max_range], not at the origin).
  static std::size_t usable_points(const PointCloud& cloud, const SensorConfig& s) {
    std::size_t n = 0;
    for (const auto& p : cloud.xyz) {
      const double r = p.norm();
      n += r > 0.0 && r >= s.min_range && r <= s.max_range;
    }
    return n;
  }
  /// Flags `r` (ScanResult::degenerate) when its scan cannot constrain the odometry: no usable
  /// point, or too few edge or plane features. (The odometry flags more scans itself: those where
  /// the features leave some direction unconstrained.)
  void add(ScanResult& r, std::size_t usable, const std::string& name, bool first_scan) {
    ++processed;
    const bool few = r.n_edges < kMinFeatures || r.n_planes < kMinFeatures;
    if (usable == 0) ++without_points;
    if (usable > 0 && !few) return;
    r.degenerate = true;
    scans.push_back(r.index);
    later += !first_scan;
    if (scans.size() <= kListed)
      fmt::print(stderr, "\nwarning: {}: degenerate scan ({}); the predicted motion is kept{}\n", name,
                 usable == 0 ? "no point between min_range and max_range"
                             : fmt::format("{} edge and {} plane features", r.n_edges, r.n_planes),
                 scans.size() == kListed ? " (further degenerate scans are only counted)" : "");
  }
  [[nodiscard]] nlohmann::json json() const {
    return {{"processed", processed},
            {"degenerate", scans.size()},
            {"degenerate_scans", scans},
            {"without_usable_points", without_points},
            {"dropped_no_return_points", dropped_points}};
  }
};

/// The labels of a scan that dropped no-return points, one per point of its file (no return: unlabeled).
std::vector<Label> file_labels(const std::vector<Label>& labels, const io::ScanInfo& info) {
  if (info.kept.empty()) return labels;
  std::vector<Label> out(info.file_points, semantic::kUnlabeled);
  for (std::size_t j = 0; j < info.kept.size() && j < labels.size(); ++j) out[info.kept[j]] = labels[j];
  return out;
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
  if (!seq.sensor || !a.config.preset.empty() || io::config_file_sets(a.config.config_path, "sensor")) return;
  cfg.sensor = *seq.sensor;
  io::validate_config(cfg, "the sensor model of " + a.sequence);
  fmt::print("sensor model from the recording: {} ({} beams, {} columns, {:.1f} Hz, {:.1f} .. {:.1f} m)\n",
             cfg.sensor.preset, cfg.sensor.N_scan, cfg.sensor.Horizon_SCAN, cfg.sensor.scan_rate_hz,
             cfg.sensor.min_range, cfg.sensor.max_range);
}

void run(const RunArgs& a) {
  PipelineConfig cfg = make_config(a);
  cfg.input = apply_input_args(cfg.input, a.input);
  io::Sequence seq = io::open_sequence(a.sequence, io::input_options(cfg.input));
  for (const auto& w : seq.warnings) fmt::print(stderr, "warning: {}\n", w);
  take_recording_sensor(cfg, seq, a);
  if (a.gt_frame == "lidar") seq.calib.reset();  // poses.txt is LiDAR-frame: Tr is not applied
  if (a.gt_frame == "camera" && seq.has_poses() && !(seq.calib && seq.calib->has_Tr))
    throw InputError(a.sequence + ": --gt-frame camera needs calib.txt with Tr (velodyne -> camera 0)");
  if (seq.poses_frame_unknown()) (void)seq.lidar_poses();  // throws the explanation before any output
  const auto first = static_cast<std::size_t>(a.first);
  if (first >= seq.size())
    throw InputError(
        fmt::format("{}: --first {} but the sequence has {} scans", a.sequence, first, seq.size()));
  if (a.drop_moving && !seq.has_labels())
    throw InputError(a.sequence + ": --drop-labelled-moving needs ground-truth labels (labels/*.label)");
  const std::size_t last =
      a.count < 0 ? seq.size() : std::min(seq.size(), first + static_cast<std::size_t>(a.count));
  if (io::sensor_needs_estimate(cfg)) cfg = estimate_sensor(a, cfg, seq, first, last);
  std::string note;
  const std::shared_ptr<MovingSegmenter> cnn = run::prepare_detector(cfg, &note);
  if (!note.empty()) fmt::print(stderr, "{}\n", note);

  // The sensor model must fit the data: judged on the first scan with enough points in range,
  // before the output folder is touched (a wrong --preset leaves nothing to clean up).
  bool fit_checked = false;
  for (std::size_t i = first; i < last && i < first + 10 && !fit_checked; ++i) {
    PointCloud cloud;
    try {
      cloud = seq.read_scan(i);
    } catch (const InputError&) {
      break;  // the run reports it at this scan, with the outputs of the scans before it
    }
    const io::SensorFit fit = io::sensor_fit(cloud, cfg.sensor);
    const std::string problem = io::sensor_fit_problem(fit, cfg.sensor, seq.scan_files[i]);
    if (!problem.empty()) throw InputError(problem);
    fit_checked = fit.in_range >= io::kMinFitPoints;
  }

  const OutputDir out(a.out, a.sequence, a.overwrite);
  io::write_atomic(a.out + "/config.yaml", [&](std::ostream& o) { o << io::dump_config(cfg); });
  const bool labels_on = cfg.detection.detector != Detector::kNone;

  fmt::print("dloam run: {} scans of {} ({} preset, detector {}, de-skew {}) -> {}\n", last - first,
             a.sequence, cfg.sensor.preset, name_of(cfg.detection.detector),
             cfg.deskew.enabled ? "on" : "off", a.out);
  std::fflush(stdout);
  Pipeline pipeline(cfg, cnn);
  std::vector<ScanResult> results;
  std::vector<Pose> poses;
  Progress progress("run", last - first);
  run::LabelStats label_stats;
  DegenerateScans degenerate;
  std::string failure;  // the error that stopped the run, if one did
  const StopSignals stop;
  for (std::size_t i = first; i < last && !stop.received(); ++i) {
    try {
      io::ScanInfo info;
      const PointCloud cloud = seq.read_scan(i, &info);
      if (!fit_checked) {  // on the first scan with enough points to judge by
        const io::SensorFit fit = io::sensor_fit(cloud, cfg.sensor);
        const std::string problem = io::sensor_fit_problem(fit, cfg.sensor, seq.scan_files[i]);
        if (!problem.empty()) throw InputError(problem);
        fit_checked = fit.in_range >= io::kMinFitPoints;
      }
      const std::vector<Label> gt =
          seq.has_labels() ? seq.read_scan_labels(i, cloud.size(), &info) : std::vector<Label>{};
      std::vector<std::size_t> kept;
      ScanResult r = pipeline.process(a.drop_moving ? run::without_moving(cloud, gt, kept) : cloud);
      if (a.drop_moving) run::restore_indices(r, kept, cloud.size());
      r.index = i;
      if (seq.has_labels()) label_stats.add(gt, r);
      if (labels_on)
        io::write_labels(fmt::format("{}/labels/{}.label", a.out, seq.output_name(i)),
                         file_labels(r.labels, info));
      poses.push_back(r.pose);
      // Keep only what timing.csv needs; swapping with empty vectors frees the memory (assigning {}
      // keeps the capacity: about 1 MB a scan on a 64-beam drive).
      std::vector<Label>().swap(r.labels);
      r.n_edges = r.edge_features.size();
      r.n_planes = r.plane_features.size();
      std::vector<std::size_t>().swap(r.edge_features);
      std::vector<std::size_t>().swap(r.plane_features);
      std::vector<std::size_t>().swap(r.map_points);
      degenerate.dropped_points += info.dropped();
      degenerate.add(r, DegenerateScans::usable_points(cloud, cfg.sensor), seq.scan_files[i], i == first);
      results.push_back(std::move(r));
    } catch (const std::exception& e) {
      failure = e.what();
      break;
    }
    if (results.size() % 50 == 0)
      write_trajectories(a.out, seq, results, poses);  // an interrupted run keeps its poses
    progress.update(results.size(), fmt::format("{:.0f} ms/scan", results.back().times[Module::kTotal]));
  }
  if (stop.received())
    fmt::print(stderr, "\n{}: stopping; writing the outputs of the {} scans processed\n",
               StopSignals::name(stop.received()), results.size());
  if (!failure.empty() && results.empty()) {  // nothing to keep: the folder is left as it was found
    std::error_code ec;
    fs::remove(a.out + "/config.yaml", ec);
    throw InputError(failure);
  }
  if (!failure.empty())
    fmt::print(stderr, "\nerror: {}\nwriting the outputs of the {} scans before it\n", failure,
               results.size());

  // Mapping-refined trajectory (loop closures move earlier scans too); after a failure inside the
  // pipeline, the real-time poses when the refined ones cannot be had.
  try {
    std::vector<Pose> refined = pipeline.trajectory();
    if (refined.size() >= poses.size())
      poses.assign(refined.begin(), refined.begin() + static_cast<long>(poses.size()));
  } catch (const std::exception& e) {
    if (failure.empty()) failure = e.what();
    fmt::print(stderr, "the mapping-refined poses are unavailable ({}): writing the real-time poses\n",
               e.what());
  }
  write_trajectories(a.out, seq, results, poses);
  io::write_timing_csv(a.out + "/timing.csv", results);
  PointCloud map;
  try {
    map.xyz = pipeline.global_map();
  } catch (const std::exception& e) {
    if (failure.empty()) failure = e.what();
    fmt::print(stderr, "the global map is unavailable ({}): map.ply is empty\n", e.what());
  }
  io::write_ply(a.out + "/map.ply", map);
  print_summary(results);
  std::size_t loops = 0;
  try {
    loops = pipeline.loop_closures();
  } catch (const std::exception&) {  // the failure is reported above
  }
  print_tracking(results);
  fmt::print("loop closures: {}\n", loops);
  if (seq.source) fmt::print("input: {}\n", seq.source->describe());
  if (degenerate.dropped_points)
    fmt::print("no-return (NaN) points dropped by the reader: {}\n", degenerate.dropped_points);
  fmt::print(
      "degenerate scans: {} of {} ({} without a point in range){}\n", degenerate.scans.size(), results.size(),
      degenerate.without_points,
      degenerate.scans.empty() ? "" : ": the predicted motion was kept there (metrics.json lists them)");
  fmt::print(
      "wrote {}/poses.txt, poses_tum.txt, map.ply ({} points), timing.csv, config.yaml, metrics.json{}\n",
      a.out, map.size(), labels_on ? ", labels/" : "");

  if (seq.has_poses() && !poses.empty()) {
    const auto gt_all = seq.lidar_poses();
    const std::vector<Pose> gt(gt_all.begin() + static_cast<long>(first),
                               gt_all.begin() + static_cast<long>(first + poses.size()));
    write_odometry_metrics(a.out + "/metrics.json", gt, poses, a.lengths);
  }
  if (seq.has_labels() && !results.empty()) write_label_stats(label_stats, a.out + "/metrics.json");
  merge_tracking_summary(a.out + "/metrics.json", results);
  nlohmann::json metrics = read_metrics(a.out + "/metrics.json");
  metrics["scans"] = degenerate.json();
  io::write_atomic(a.out + "/metrics.json", [&](std::ostream& o) { o << metrics.dump(2) << '\n'; });

  if (!failure.empty())
    throw InputError(
        fmt::format("{} (the outputs of the {} scans before it are in {})", failure, results.size(), a.out));
  if (!results.empty() && degenerate.without_points == results.size())
    throw InputError(fmt::format(
        "{}: none of the {} scans has a point between min_range {} m and max_range {} m of the sensor model: "
        "no usable input (wrong unit, empty scans, or sensor.min_range / max_range?)",
        a.sequence, results.size(), cfg.sensor.min_range, cfg.sensor.max_range));
  if (results.size() > 1 && degenerate.later + 1 == results.size())
    throw InputError(
        fmt::format("{}: every scan after the first is degenerate (too few features to register): "
                    "the poses are only the predicted motion",
                    a.sequence));
  if (a.report) write_html_report(a.out, a.out + "/report.html");
  if (stop.received()) {
    std::fflush(stdout);
    throw CLI::RuntimeError(128 + stop.received());  // as a shell reports a process ended by the signal
  }
  if (a.clean) {
    fmt::print("\n");
    clean_sequence(seq, poses, first, cfg, a.out + "/clean");
  }
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
      "metrics.json (degenerate scans; errors against poses.txt and labels/ when the folder has them); with "
      "--clean also clean/ (see `dloam clean`).\n"
      "A folder with the outputs of an earlier run is refused unless --overwrite; two runs cannot write\n"
      "into one folder at once. SIGINT, SIGTERM and SIGHUP stop after the current scan with complete files.\n"
      "Examples:\n"
      "  dloam run ../shared/data/kitti-raw-0005 --out out/0005 --config kitti-raw --report\n"
      "  dloam run sim/urban --out out/urban --preset HDL-64E --detector none --overwrite\n"
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
  cmd->add_flag("--overwrite", args->overwrite, "delete the outputs of an earlier run in --out first");
  ConfigHelp config_help;
  config_help.preset_auto = true;
  add_config_options(cmd, args->config, config_help);
  cmd->add_option("--detector", args->detector, "dynamic-object detector: " + enum_choices<Detector>(", "))
      ->check(CLI::IsMember(enum_names_of<Detector>()));
  cmd->add_flag(
      "--drop-labelled-moving", args->drop_moving,
      "delete the points labels/ marks moving before the pipeline sees them: a perfect "
      "detector's reference for studies (use with --detector none); written labels mark them moving");
  cmd->add_flag(
      "--clean", args->clean,
      "then the whole-drive pass (`dloam clean`) over the run: labels and static map in --out/clean");
  cmd->add_option("--deskew", args->deskew, "override the config's de-skew switch")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--gt-frame", args->gt_frame,
                  "frame of the folder's poses.txt: auto (camera when calib.txt has Tr, LiDAR without "
                  "calib.txt; a calib.txt without Tr is an error), lidar, camera")
      ->check(CLI::IsMember({"auto", "lidar", "camera"}))
      ->capture_default_str();
  cmd->add_option(
         "--platform", args->platform,
         "motion limits of the platform (the config's motion section): car (default), handheld, legged")
      ->check(CLI::IsMember(motion_platform_names()));
  cmd->add_option("--lengths", args->lengths,
                  "segment lengths (m) for metrics.json; default: devkit 100..800, "
                  "or 5,10,20,30 with every frame as a start on drives under 200 m")
      ->delimiter(',')
      ->check(positive_number());
  cmd->add_option("--first", args->first, "first scan index")->check(integer_at_least(0));
  cmd->add_option("--count", args->count, "number of scans (default: all)")->check(integer_at_least(1));
  cmd->add_flag("--report", args->report, "also write report.html (as `dloam report OUT`)");
  cmd->callback([args] { run(*args); });
}

}  // namespace dloam::app
