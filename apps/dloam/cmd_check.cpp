// `dloam check SEQUENCE_DIR`: validates every file of a sequence (scans, labels, poses, calib,
// times), prints each problem with its file name and a summary (points per scan, ground truth
// present, moving points, the sensor preset the data matches); exits non-zero on any problem.
#include <fmt/core.h>

#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/sequence_check.hpp"

namespace dloam::app {
namespace {

struct CheckArgs {
  std::string dir, topic, preset, config_path;
};

std::string yes_no(bool present) { return present ? "yes" : "no"; }

void print_summary(const io::SequenceReport& r, const std::string& preset) {
  fmt::print("sequence      {}\n", r.dir);
  if (r.source.empty())
    fmt::print("scans         {} {} files, {} readable\n", r.scans, r.scan_format, r.scans_ok);
  else
    fmt::print("scans         {} {} messages, {} readable\nsource        {}\n", r.scans, r.scan_format,
               r.scans_ok, r.source);
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
    const auto& s = *r.sensor;
    fmt::print(
        "sensor        elevation {:.1f} .. {:.1f} deg, {} beams resolved -> looks like {} "
        "(field-of-view overlap {:.2f})\n",
        s.lowest_deg, s.highest_deg, s.resolved_beams, s.preset, s.fov_overlap);
    if (!preset.empty() && sensor_preset(preset).preset != s.preset)
      fmt::print("warning       --preset {} given, but the data looks like {}\n", preset, s.preset);
  }
  if (r.fit && r.fit->in_range > 0)
    fmt::print("sensor fit    {:.1f} % of the first full scan's points in range lie on a beam of {}\n",
               100.0 * static_cast<double>(r.fit->inside) / static_cast<double>(r.fit->in_range),
               r.fit_sensor);
}

void run_check(const CheckArgs& a) {
  io::CheckOptions options;
  options.topic = a.topic;
  // The sensor `dloam run` would use with the same options: scans that do not fit it are problems.
  if (!a.preset.empty() || !a.config_path.empty())
    options.sensor = io::config_from(a.preset, a.config_path).sensor;
  options.on_problem = [](const std::string& problem) {
    fmt::print(stderr, "problem: {}\n", problem);
    std::fflush(stderr);
  };
  options.on_warning = [](const std::string& warning) {
    fmt::print(stderr, "warning: {}\n", warning);
    std::fflush(stderr);
  };
  const auto report = io::check_sequence(a.dir, options);
  print_summary(report, a.preset);
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
         "times.txt; or a rosbag (.bag) of sensor_msgs/PointCloud2")
      ->required();
  cmd->add_option("--topic", args->topic, "rosbag: the PointCloud2 topic (default: the only one)");
  cmd->add_option(
      "--preset", args->preset,
      "sensor you expect (HDL-64E, HDL-32E, VLP-16, OS1-64, OS1-128): scans that do not fit it are "
      "problems, as in `dloam run`");
  cmd->add_option("--config,-c", args->config_path,
                  "YAML config whose sensor the scans must fit, as in `dloam run`")
      ->check(CLI::ExistingFile);
  cmd->footer(
      "Reads every scan fully and every label, pose, time and calibration file; reports each problem\n"
      "with its file name and keeps going. Exit status 0 when everything is readable and consistent.\n"
      "Examples:\n"
      "  dloam check ../shared/data/kitti-raw-0005\n"
      "  dloam check recordings/campus_pcd --preset VLP-16\n"
      "  dloam check drive.bag --topic /velodyne_points");
  cmd->callback([args] { run_check(*args); });
}

}  // namespace dloam::app
