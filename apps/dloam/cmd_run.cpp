// `dloam run`: the SLAM pipeline over a sequence folder or recording, into the output folder of
// run::RunOutputs (the same writer as dloam_node's and the Python module's), through
// run::run_sequence; this file adds the command line, the sensor model's choice and the terminal
// report. SIGINT, SIGTERM and SIGHUP stop after the current scan, and an error in a scan stops the
// run there: the outputs of the scans processed are written complete either way.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <optional>

#include "clean_pass.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "config_args.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/input_options.hpp"
#include "dloam/io/sensor_estimate.hpp"
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

/// The ground-truth label statistics: Table III's effective features, the moving share of the
/// points sent to the map, MOS when a detector wrote labels.
void print_label_stats(const run::LabelStats& stats) {
  fmt::print(
      "effective features (Table III): {}; moving points sent to the map: {}\n",
      stats.features.total
          ? fmt::format("{:.2f} % of {}", 100.0 * stats.features.ratio(), stats.features.total)
          : "none on labelled points",
      stats.map_points ? fmt::format("{:.3f} %", 100.0 * stats.map_moving_fraction()) : "no point sent");
  if (stats.detector) print_mos(stats.mos);
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
  if (t["detection_suspended_scans"].get<std::size_t>() > 0)
    fmt::print("scans without detection (the step fitted too poorly to tell moving objects): {}\n",
               t["detection_suspended_scans"].get<std::size_t>());
  if (t["lost_steps"].get<std::size_t>() > 0)
    fmt::print("steps that could not be estimated (listed in metrics.json): {}\n",
               t["lost_steps"].get<std::size_t>());
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

  fmt::print("dloam run: {} scans of {} ({} preset, detector {}, de-skew {}) -> {}\n", last - first,
             a.sequence, cfg.sensor.preset, name_of(cfg.detection.detector),
             cfg.deskew.enabled ? "on" : "off", a.out);
  std::fflush(stdout);
  Progress progress("run", last - first);
  const StopSignals stop;
  std::optional<OutputDir> out_dir;
  run::RunOptions options;
  options.out = a.out;
  options.first = first;
  options.count = last - first;
  options.drop_labelled_moving = a.drop_moving;
  options.lengths = a.lengths;
  options.before_output = [&] { out_dir.emplace(a.out, a.sequence, a.overwrite); };
  options.stop = [&] { return stop.received() != 0; };
  options.on_warning = [](const std::string& w) { fmt::print(stderr, "\nwarning: {}\n", w); };
  options.on_scan = [&](std::size_t done, std::size_t, const ScanResult& r) {
    progress.update(done, fmt::format("{:.0f} ms/scan", r.times[Module::kTotal]));
  };
  const run::SequenceRun result = run::run_sequence(seq, cfg, cnn, options);
  const run::RunSummary& s = result.summary;
  if (result.stopped)
    fmt::print(stderr, "\n{}: stopping; writing the outputs of the {} scans processed\n",
               StopSignals::name(stop.received()), s.scans);
  if (!result.error.empty())
    fmt::print(stderr, "\nerror: {}\nwrote the outputs of the {} scans before it\n", result.error, s.scans);
  for (const auto& problem : s.problems) fmt::print(stderr, "{}\n", problem);

  print_summary(s.results);
  print_tracking(s.results);
  fmt::print("loop closures: {}\n", s.loop_closures);
  if (seq.source) fmt::print("input: {}\n", seq.source->describe());
  if (s.dropped_points) fmt::print("no-return (NaN) points dropped by the reader: {}\n", s.dropped_points);
  fmt::print("degenerate scans: {} of {} ({} without a point in range){}\n", s.degenerate, s.scans,
             s.without_usable_points,
             s.degenerate == 0 ? "" : ": the predicted motion was kept there (metrics.json lists them)");
  fmt::print(
      "wrote {}/poses.txt, poses_tum.txt, map.ply ({} points), moving.ply ({} points), timing.csv, "
      "config.yaml, metrics.json{}\n",
      a.out, s.map_points, s.moving_points, cfg.detection.detector != Detector::kNone ? ", labels/" : "");
  if (s.odometry) print_odometry(*s.odometry, "lidar");
  if (s.labels) print_label_stats(*s.labels);

  const std::string failure = !result.error.empty() ? result.error
                              : s.problems.empty()  ? std::string()
                                                    : s.problems.front();
  if (!failure.empty())
    throw InputError(
        fmt::format("{} (the outputs of the {} scans before it are in {})", failure, s.scans, a.out));
  if (s.scans > 0 && s.without_usable_points == s.scans)
    throw InputError(fmt::format(
        "{}: none of the {} scans has a point between min_range {} m and max_range {} m of the sensor model: "
        "no usable input (wrong unit, empty scans, or sensor.min_range / max_range?)",
        a.sequence, s.scans, cfg.sensor.min_range, cfg.sensor.max_range));
  if (s.all_degenerate_after_first)
    throw InputError(
        fmt::format("{}: every scan after the first is degenerate (too few features to register): "
                    "the poses are only the predicted motion",
                    a.sequence));
  if (a.report) write_html_report(a.out, a.out + "/report.html");
  if (result.stopped) {
    std::fflush(stdout);
    throw CLI::RuntimeError(128 + stop.received());  // as a shell reports a process ended by the signal
  }
  if (a.clean) {
    fmt::print("\n");
    clean_sequence(seq, s.trajectory, first, cfg, a.out + "/clean");
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
      "Outputs in --out: poses.txt (KITTI, camera frame when calib.txt has Tr, with that calib.txt),\n"
      "poses_tum.txt, poses_gt.txt (the ground truth of the scans run, when known), map.ply, moving.ply\n"
      "(the points labelled moving), timing.csv (ms per scan and module), config.yaml (the full config\n"
      "used), labels/ (detector on), metrics.json (tracking, degenerate scans; errors against poses.txt\n"
      "and labels/ when the folder has them); with --report also report.html, with --clean clean/.\n"
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
