// `dloam check SEQUENCE_DIR`: validates every file of a sequence (scans, labels, poses, calib,
// times), prints each problem with its file name and a summary (points per scan, ground truth
// present, moving points, the sensor model estimated from the scans and the preset nearest to it);
// exits non-zero on any problem. --write-sensor writes the estimated model as a YAML sensor section.
#include <fmt/core.h>

#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "config_args.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/input_options.hpp"
#include "dloam/io/sequence_check.hpp"
#include "input_args.hpp"

namespace dloam::app {
namespace {

struct CheckArgs {
  std::string dir, write_sensor;
  ConfigArgs config;
  InputArgs input;
};

std::string yes_no(bool present) { return present ? "yes" : "no"; }

void print_summary(const io::SequenceReport& r, const std::string& preset) {
  fmt::print("sequence      {}\n", r.dir);
  if (r.scan_format.empty())
    fmt::print("scans         none (the input could not be opened)\n");
  else if (r.source.empty())
    fmt::print("scans         {} {} files, {} readable\n", r.scans, r.scan_format, r.scans_ok);
  else if (r.recording_sensor)
    fmt::print("scans         {} decoded from raw packets, {} readable\nsource        {}\n", r.scans,
               r.scans_ok, r.source);
  else
    fmt::print("scans         {} {} messages, {} readable\nsource        {}\n", r.scans, r.scan_format,
               r.scans_ok, r.source);
  if (r.recording_sensor) {
    const SensorConfig& s = *r.recording_sensor;
    fmt::print(
        "sensor model  {} from the recording: {} beams ({:.1f} .. {:.1f} deg), {} columns, {:.2f} Hz, "
        "{:.2f} .. {:.1f} m (used by `dloam run` without --preset)\n",
        s.preset, s.N_scan, s.beam_elevation_deg(0), s.beam_elevation_deg(s.N_scan - 1), s.Horizon_SCAN,
        s.scan_rate_hz, s.min_range, s.max_range);
  }
  if (r.scans_ok > 0) {
    fmt::print("points/scan   min {}  mean {:.0f}  max {}\n", r.min_points, r.mean_points, r.max_points);
    fmt::print("point times   {}\n", r.points_with_time == r.scans_ok ? "per-point time channel in every scan"
                                     : r.points_with_time == 0        ? "none (time from azimuth)"
                                                                      : "only in some scans");
    if (r.dropped_points) fmt::print("no returns    {} NaN points dropped by the reader\n", r.dropped_points);
    fmt::print("degenerate    {} scan{}{}\n", r.degenerate_scans, r.degenerate_scans == 1 ? "" : "s",
               r.degenerate_scans ? " (listed above): too few points to register" : "");
  }
  fmt::print("labels        {}", yes_no(r.has_labels));
  if (r.has_labels) {
    const double pct = r.labelled_points ? 100.0 * r.moving_points / r.labelled_points : 0.0;
    fmt::print(" ({} files; {} labelled points, {} moving = {:.2f} %; {} unlabelled/outlier)", r.label_files,
               r.labelled_points, r.moving_points, pct, r.ignored_points);
  }
  fmt::print("\nposes         {}", yes_no(r.has_poses));
  if (r.has_poses) fmt::print(" ({} poses, LiDAR path {:.2f} m)", r.pose_count, r.path_length_m);
  fmt::print("\ncalib Tr      {}", r.has_calib ? yes_no(r.calib_has_Tr) : "no calib.txt");
  if (r.has_calib) {
    std::string keys;
    for (const auto& k : r.calib_keys) keys += (keys.empty() ? "" : " ") + k;
    fmt::print(" (calib.txt keys: {})", keys);
  }
  fmt::print("\ntimes         {}", yes_no(r.has_times));
  if (r.has_times && r.time_count > 1 && r.last_time > r.first_time) {
    const double rate = static_cast<double>(r.time_count - 1) / (r.last_time - r.first_time);
    fmt::print(" ({} times, {:.3f} .. {:.3f} s, {:.2f} Hz)", r.time_count, r.first_time, r.last_time, rate);
  }
  fmt::print("\n");
  if (r.sensor) {
    const auto lines = io::describe_estimate(*r.sensor);
    for (std::size_t i = 0; i < lines.size(); ++i)
      fmt::print("{}{}\n", i == 0 ? "sensor        " : "              ", lines[i]);
    if (!preset.empty()) {
      const PresetMatch m = match_preset(r.sensor->sensor, preset);
      if (!m.resembles)
        fmt::print(
            "warning       --preset {} given, but the data's beams differ from it (mean distance {:.3f} deg, "
            "{} vs {} beams)\n",
            m.preset, m.distance_deg, r.sensor->sensor.N_scan, m.preset_beams);
    }
  } else if (!r.sensor_error.empty()) {
    fmt::print("sensor        not estimated: {}\n", r.sensor_error);
  }
  if (r.fit && r.fit->in_range > 0)
    fmt::print("sensor fit    {:.1f} % of the first full scan's points in range lie on a beam of {}\n",
               100.0 * static_cast<double>(r.fit->inside) / static_cast<double>(r.fit->in_range),
               r.fit_sensor);
}

void run_check(const CheckArgs& a) {
  if (!a.config.preset.empty())
    (void)sensor_preset(a.config.preset);  // reject an unknown name before reading
  io::CheckOptions options;
  options.input = io::input_options(apply_input_args(InputConfig{}, a.input));
  if (!a.config.config_path.empty()) {  // its vertical-angle correction applies to the points estimated from
    const PipelineConfig file = io::config_from_allowing_auto("", a.config.config_path);
    options.estimation.vertical_angle_correction_deg = file.sensor.vertical_angle_correction_deg;
  }
  // The sensor `dloam run` would use with the same options: scans that do not fit it are problems.
  if (!a.config.preset.empty() || !a.config.config_path.empty()) {
    const PipelineConfig cfg = io::config_from_allowing_auto(a.config.preset, a.config.config_path);
    if (!io::sensor_needs_estimate(cfg)) options.sensor = cfg.sensor;
  }
  options.on_problem = [](const std::string& problem) {
    fmt::print(stderr, "problem: {}\n", problem);
    std::fflush(stderr);
  };
  options.on_warning = [](const std::string& warning) {
    fmt::print(stderr, "warning: {}\n", warning);
    std::fflush(stderr);
  };
  const auto report = io::check_sequence(a.dir, options);
  print_summary(report, a.config.preset);
  if (!a.write_sensor.empty()) {
    if (!report.sensor) throw InputError(a.dir + ": no sensor model to write: " + report.sensor_error);
    const std::string yaml = io::estimated_sensor_yaml(*report.sensor, a.dir);
    io::write_atomic(a.write_sensor, [&](std::ostream& o) { o << yaml; });
    fmt::print("wrote the estimated sensor section to {}\n", a.write_sensor);
  }
  const std::string warnings = report.warnings.empty()
                                   ? ""
                                   : fmt::format(" ({} warning{} listed above)", report.warnings.size(),
                                                 report.warnings.size() == 1 ? "" : "s");
  if (report.problems.empty()) {
    fmt::print("OK: no problems found{}\n", warnings);
    return;
  }
  fmt::print("FAILED: {} problem{} (listed above){}\n", report.problems.size(),
             report.problems.size() == 1 ? "" : "s", warnings);
  std::fflush(stdout);
  throw CLI::RuntimeError(1);
}

}  // namespace

void register_check(CLI::App& app) {
  auto args = std::make_shared<CheckArgs>();
  auto* cmd = app.add_subcommand("check", "validate every file of a sequence folder and summarise it");
  cmd->add_option(
         "sequence", args->dir,
         "folder with velodyne/*.bin (KITTI) or *.pcd scans; optional labels/, poses.txt, calib.txt, "
         "times.txt; a bag (.bag, .db3, .mcap, rosbag2 folder) of PointCloud2 or raw packets; a capture "
         "(.pcap, .pcapng)")
      ->required();
  add_input_options(cmd, args->input);
  ConfigHelp config_help;
  config_help.preset =
      "sensor you expect ({presets}; auto: estimated): scans that do not fit it are problems, as in `dloam "
      "run`; "
      "warns if the data's beams differ from it";
  config_help.config =
      "YAML config (or shipped name) whose sensor the scans must fit, as in `dloam run`; its "
      "sensor.vertical_angle_correction_deg is applied before estimating (e.g. kitti-raw: 0.22 for KITTI)";
  add_config_options(cmd, args->config, config_help);
  cmd->add_option("--write-sensor", args->write_sensor,
                  "write the estimated sensor model as a YAML sensor section (for --config); fails when "
                  "the scans do not determine one");
  cmd->footer(
      "Reads every scan fully and every label, pose, time and calibration file; reports each problem\n"
      "with its file name and keeps going. Exit status 0 when everything is readable and consistent.\n"
      "The sensor model (beams, origin heights, columns, range limits, scan rate) is estimated from\n"
      "12 scans spread over the sequence and compared with the built-in presets.\n"
      "Examples:\n"
      "  dloam check ../shared/data/kitti-raw-0005\n"
      "  dloam check recordings/campus_pcd --preset VLP-16\n"
      "  dloam check recordings/wide_pcd --write-sensor wide.yaml && dloam run recordings/wide_pcd --config "
      "wide.yaml --out out\n"
      "  dloam check drive.bag --topic /velodyne_points\n"
      "  dloam check vlp16.pcap\n"
      "  dloam check os1.pcap --metadata os1.json");
  cmd->callback([args] { run_check(*args); });
}

}  // namespace dloam::app
