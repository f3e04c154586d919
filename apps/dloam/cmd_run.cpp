// `dloam run`: the SLAM pipeline over a sequence folder or recording. Writes the output folder of
// run/run_outputs.hpp (poses KITTI + TUM, the global map, moving points, timing, the full config,
// labels when a detector is on, metrics), and with --report the HTML report of it. Ctrl-C stops
// after the current scan and still writes complete outputs for the scans processed.
#include <fmt/core.h>
#include <fmt/ranges.h>

#include <atomic>
#include <csignal>

#include "commands.hpp"
#include "config_args.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/input_options.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/sensor_estimate.hpp"
#include "dloam/pipeline/pipeline.hpp"
#include "dloam/run/detector_setup.hpp"
#include "dloam/run/run_sequence.hpp"
#include "enum_option.hpp"
#include "html_report.hpp"
#include "input_args.hpp"
#include "odometry_table.hpp"
#include "progress.hpp"

namespace dloam::app {
namespace {

namespace fs = std::filesystem;
std::atomic<bool> g_stop{false};

struct RunArgs {
  std::string sequence, out, detector, deskew, platform;
  ConfigArgs config;
  InputArgs input;
  std::vector<double> lengths;
  long first = 0, count = -1;
  bool drop_moving = false, report = false;
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

void print_label_stats(const run::LabelStats& s) {
  fmt::print("effective features (Table III): {:.2f} % of {}; moving points sent to the map: {:.3f} %\n",
             100.0 * s.features.ratio(), s.features.total, 100.0 * s.map_moving_fraction());
  if (s.detector) print_mos(s.mos);
}

void run(const RunArgs& a) {
  PipelineConfig cfg = make_config(a);
  cfg.input = apply_input_args(cfg.input, a.input);
  const io::Sequence seq = io::open_sequence(a.sequence, io::input_options(cfg.input));
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
  std::string note;
  const std::shared_ptr<MovingSegmenter> cnn = run::prepare_detector(cfg, &note);
  if (!note.empty()) fmt::print(stderr, "{}\n", note);

  fmt::print("dloam run: {} scans of {} ({} preset, detector {}, de-skew {}) -> {}\n", last - first,
             a.sequence, cfg.sensor.preset, name_of(cfg.detection.detector),
             cfg.deskew.enabled ? "on" : "off", a.out);
  run::RunOptions options;
  options.out = a.out;
  options.first = first;
  options.count = last - first;
  options.drop_labelled_moving = a.drop_moving;
  options.lengths = a.lengths;
  Progress progress("run", last - first);
  options.on_scan = [&](std::size_t done, std::size_t, const ScanResult& r) {
    progress.update(done, fmt::format("{:.0f} ms/scan", r.times[Module::kTotal]));
  };
  g_stop = false;
  options.stop = &g_stop;
  auto previous_handler = std::signal(SIGINT, [](int) { g_stop = true; });
  run::SequenceRun result;
  try {
    result = run::run_sequence(seq, cfg, cnn, options);
  } catch (...) {
    std::signal(SIGINT, previous_handler);
    throw;
  }
  std::signal(SIGINT, previous_handler);
  const run::RunSummary& summary = result.summary;
  if (result.stopped)
    fmt::print(stderr, "\ninterrupted: wrote the outputs of the {} scans processed\n", summary.scans);
  print_summary(summary.results);
  print_tracking(summary.results);
  fmt::print("loop closures: {}\n", summary.loop_closures);
  if (seq.source) fmt::print("input: {}\n", seq.source->describe());
  fmt::print(
      "wrote {}/poses.txt, poses_tum.txt, map.ply ({} points), moving.ply, timing.csv, config.yaml{}{}\n",
      a.out, summary.map_points, cfg.detection.detector != Detector::kNone ? ", labels/" : "",
      summary.odometry ? ", poses_gt.txt" : "");
  if (summary.odometry) print_odometry(*summary.odometry, "lidar");
  if (summary.labels) print_label_stats(*summary.labels);
  fmt::print("wrote {}/metrics.json\n", a.out);
  if (a.report) write_html_report(a.out, a.out + "/report.html");
  if (result.stopped) throw InputError("interrupted by the user (outputs written)");
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
      "moving.ply, poses_gt.txt and calib.txt (when the folder has them), metrics.json.\n"
      "Examples:\n"
      "  dloam run ../shared/data/kitti-raw-0005 --out out/0005 --config kitti-raw --report\n"
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
  ConfigHelp config_help;
  config_help.preset_auto = true;
  add_config_options(cmd, args->config, config_help);
  cmd->add_option("--detector", args->detector, "dynamic-object detector: " + enum_choices<Detector>(", "))
      ->check(CLI::IsMember(enum_names_of<Detector>()));
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
  cmd->add_flag("--report", args->report, "also write report.html (as `dloam report OUT`)");
  cmd->callback([args] { run(*args); });
}

}  // namespace dloam::app
