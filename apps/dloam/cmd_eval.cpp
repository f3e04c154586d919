// `dloam eval odometry|mos`: reads trajectories or label folders, runs the evaluators of
// src/dloam/eval (KITTI devkit relative error, ATE, RPE; SemanticKITTI MOS IoU and the paper's
// object-level IoU, eq. 16), prints a table and optionally writes JSON and a gnuplot PNG.
#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "clean_pass.hpp"
#include "cli_checks.hpp"
#include "commands.hpp"
#include "dloam/eval/map_metrics.hpp"
#include "dloam/eval/mos_metrics.hpp"
#include "dloam/eval/odometry_metrics.hpp"
#include "dloam/eval/plot.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/ply.hpp"
#include "dloam/run/metrics.hpp"
#include "gnuplot.hpp"
#include "odometry_table.hpp"

namespace dloam::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct OdometryArgs {
  std::string gt, est, calib, format = "kitti", json_path, plot_path;
  std::vector<double> lengths;
  std::size_t step = 10;
};

struct MapArgs {
  std::string map, sequence, poses, config_path, json_path;
  eval::MapAccuracyConfig eval;
};

struct MosArgs {
  std::string gt_dir, pred_dir, json_path;
  double object_threshold = 0.5;
};

std::vector<Pose> read_trajectory(const std::string& path, const std::string& format) {
  std::vector<Pose> poses;
  if (format == "tum") {
    for (const auto& stamped : io::read_tum_poses(path)) poses.push_back(stamped.pose);
  } else {
    poses = io::read_kitti_poses(path);
  }
  if (poses.empty()) throw InputError(path + ": no poses");
  return poses;
}

void write_json(const std::string& path, const json& doc) {
  io::write_atomic(path, [&](std::ostream& out) { out << doc.dump(2) << '\n'; });
  fmt::print("wrote {}\n", path);
}

void write_plot(const std::string& png_path, const std::vector<Pose>& gt, const std::vector<Pose>& est,
                const eval::OdometryResult& result, bool top_view_is_xz) {
  render_png(png_path, [&](const std::string& tmp, const std::string& term) {
    eval::PlotOptions options;
    options.png_path = tmp;
    options.terminal = term;
    options.vertical_axis = top_view_is_xz ? 2 : 1;
    options.title =
        result.relative.segments.empty()
            ? fmt::format("no segment   ATE {:.3f} m (aligned {:.3f} m)", result.ate.rmse,
                          result.ate_aligned.rmse)
            : fmt::format("t_rel {:.3f} %   r_rel {:.4f} deg/100 m   ATE {:.3f} m (aligned {:.3f} m)",
                          result.relative.t_rel_pct, result.relative.r_rel_deg100m, result.ate.rmse,
                          result.ate_aligned.rmse);
    return eval::odometry_plot_script(gt, est, result.relative.per_length, options);
  });
}

void run_odometry(const OdometryArgs& args, bool lengths_given, bool step_given) {
  std::vector<Pose> gt = read_trajectory(args.gt, args.format);
  std::vector<Pose> est = read_trajectory(args.est, args.format);
  if (gt.size() != est.size()) {
    throw InputError(fmt::format("ground truth {} has {} poses but estimate {} has {}", args.gt, gt.size(),
                                 args.est, est.size()));
  }
  if (!args.calib.empty()) {
    const io::Calib calib = io::read_calib(args.calib);
    if (!calib.has_Tr) throw InputError(args.calib + ": no Tr entry (velodyne -> camera 0)");
    gt = io::camera_to_lidar(gt, calib.Tr);
    est = io::camera_to_lidar(est, calib.Tr);
  }
  eval::SegmentOptions options;
  if (lengths_given) options.lengths = args.lengths;
  options.step = step_given ? args.step : (lengths_given ? 1 : 10);
  const eval::OdometryResult r = eval::evaluate_odometry(gt, est, options);

  const std::string frame = args.calib.empty() ? "as given" : "lidar (Tr^-1 P Tr)";
  print_odometry(r, frame);
  if (!args.json_path.empty()) {
    json doc = run::odometry_json(r, options, frame);
    doc["gt"] = args.gt;
    doc["estimate"] = args.est;
    write_json(args.json_path, doc);
  }
  // KITTI camera frame (no calib): y points down, so the top view is x-z; LiDAR/TUM: x-y.
  if (!args.plot_path.empty())
    write_plot(args.plot_path, gt, est, r, args.calib.empty() && args.format == "kitti");
}

/// The .label files of a folder in natural order (any file type: reading one that is not a
/// regular file names the problem).
std::vector<std::string> label_files(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(dir + ": not a folder");
  std::vector<std::string> files;
  fs::directory_iterator it(dir, ec);
  for (; !ec && it != fs::directory_iterator(); it.increment(ec))
    if (it->path().extension() == ".label") files.push_back(it->path().string());
  if (ec) throw InputError(dir + ": cannot be listed (" + ec.message() + ")");
  std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
    return io::natural_less(fs::path(a).filename().string(), fs::path(b).filename().string());
  });
  if (files.empty()) throw InputError(dir + ": no .label files");
  return files;
}

void run_mos(const MosArgs& args) {
  std::error_code ec;
  if (!fs::is_directory(args.pred_dir, ec)) throw InputError(args.pred_dir + ": not a folder");
  eval::MosResult r;
  const std::vector<std::string> gt_files = label_files(args.gt_dir);
  for (const std::string& gt_file : gt_files) {
    const fs::path pred_file = fs::path(args.pred_dir) / fs::path(gt_file).filename();
    if (fs::symlink_status(pred_file, ec).type() == fs::file_type::not_found) {
      throw InputError(
          fmt::format("{}: missing prediction for ground truth {}", pred_file.string(), gt_file));
    }
    const std::string bytes = io::read_file(gt_file);
    const auto gt = io::parse_labels(bytes, gt_file, bytes.size() / sizeof(Label));
    const auto pred = io::read_labels(pred_file.string(), gt.size());
    eval::add_scan(r, gt, pred, args.object_threshold);
  }
  std::size_t unmatched = 0;  // predictions without ground truth are not scored: say so
  for (const std::string& pred_file : label_files(args.pred_dir))
    unmatched += fs::symlink_status(fs::path(args.gt_dir) / fs::path(pred_file).filename(), ec).type() ==
                 fs::file_type::not_found;
  if (unmatched)
    fmt::print(stderr, "warning: {} .label files of {} have no ground truth in {} and are not scored\n",
               unmatched, args.pred_dir, args.gt_dir);
  print_mos(r, args.object_threshold);
  if (!args.json_path.empty()) {
    json doc = run::mos_json(r, args.object_threshold);
    doc["gt_dir"] = args.gt_dir;
    doc["pred_dir"] = args.pred_dir;
    write_json(args.json_path, doc);
  }
}

void run_map(const MapArgs& args) {
  const io::PlyCloud map = io::read_ply(args.map);
  const io::Sequence seq = io::open_sequence(args.sequence);
  if (!seq.has_labels()) throw InputError(args.sequence + ": no ground-truth labels (labels/*.label)");
  std::vector<Pose> poses = io::read_kitti_poses(args.poses);
  if (poses.empty()) throw InputError(args.poses + ": no poses");
  if (poses.size() > seq.size())
    throw InputError(
        fmt::format("{}: {} poses but {} has {} scans", args.poses, poses.size(), args.sequence, seq.size()));
  if (seq.calib && seq.calib->has_Tr) poses = io::camera_to_lidar(poses, seq.calib->Tr);
  // The points as the pipeline maps them: vertical-angle corrected and de-skewed with the poses
  // (as the config says; no config: as stored).
  PipelineConfig cfg = io::config_from("", args.config_path);
  if (args.config_path.empty()) cfg.deskew.enabled = false;
  std::vector<double> stamps;
  if (seq.times.size() >= poses.size())
    stamps.assign(seq.times.begin(), seq.times.begin() + static_cast<long>(poses.size()));
  eval::MapAccuracyEvaluator evaluator(args.eval);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const PointCloud cloud = seq.read_scan(i);
    evaluator.add_scan(drive_scan_points(cloud, poses, i, stamps, cfg), seq.read_scan_labels(i, cloud.size()),
                       poses[i]);
  }
  const eval::MapAccuracy r = evaluator.evaluate(map.cloud.xyz);
  fmt::print("map {}: {} points; reference: {} voxels of {:g} m from {} scans (points within {:g} m)\n",
             args.map, r.map_points, evaluator.reference_voxels(), args.eval.leaf, poses.size(),
             args.eval.max_range);
  fmt::print(
      "  SA {:.4f} ({} of {} static voxels kept)  DA {:.4f} ({} of {} dynamic voxels kept)  score {:.4f}\n",
      r.sa(), r.static_kept, r.static_voxels, r.da(), r.dynamic_kept, r.dynamic_voxels, r.score());
  fmt::print("  map points: {} static, {} dynamic (ghosts), {} with no labelled point within {:g} m\n",
             r.map_static, r.map_dynamic, r.map_unmatched, args.eval.radius);
  if (!args.json_path.empty()) {
    write_json(args.json_path, {{"map", args.map},
                                {"sequence", args.sequence},
                                {"poses", args.poses},
                                {"leaf", args.eval.leaf},
                                {"radius", args.eval.radius},
                                {"max_range", args.eval.max_range},
                                {"sa", r.sa()},
                                {"da", r.da()},
                                {"score", r.score()},
                                {"static_voxels", r.static_voxels},
                                {"static_kept", r.static_kept},
                                {"dynamic_voxels", r.dynamic_voxels},
                                {"dynamic_kept", r.dynamic_kept},
                                {"map_points", r.map_points},
                                {"map_static", r.map_static},
                                {"map_dynamic", r.map_dynamic},
                                {"map_unmatched", r.map_unmatched}});
  }
}

}  // namespace

void register_eval(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("eval", "Evaluate odometry (KITTI devkit, ATE, RPE) or moving-object segmentation");
  cmd->require_subcommand(1);
  cmd->footer(
      "Examples:\n"
      "  dloam eval odometry GT/poses.txt out/poses.txt --calib GT/calib.txt --lengths 5,10,20,30\n"
      "  dloam eval odometry GT/poses.txt out/poses.txt --json odo.json --plot odo.png\n"
      "  dloam eval mos GT/labels out/labels --json mos.json --object-threshold 0.5\n"
      "  dloam eval map out/clean/map.ply GT out/poses.txt --json map.json\n"
      "Without --lengths: the KITTI devkit protocol, 100,200,...,800 m segments from every 10th frame.");

  auto odo = std::make_shared<OdometryArgs>();
  auto* o = cmd->add_subcommand("odometry",
                                "KITTI devkit relative error, ATE (raw and SE(3)-aligned), per-frame RPE");
  o->add_option("GT_POSES", odo->gt, "ground-truth poses")->required()->check(CLI::ExistingFile);
  o->add_option("EST_POSES", odo->est, "estimated poses, one per ground-truth pose")
      ->required()
      ->check(CLI::ExistingFile);
  o->add_option("--calib", odo->calib,
                "KITTI calib.txt: evaluate in the LiDAR frame, Tr^-1 P Tr (default: as given)")
      ->check(CLI::ExistingFile);
  auto* lengths = o->add_option("--lengths", odo->lengths, "segment lengths in metres (default 100,...,800)")
                      ->delimiter(',')
                      ->check(positive_number());
  auto* step =
      o->add_option("--step", odo->step, "a segment starts every N frames (default 10; 1 with --lengths)")
          ->check(CLI::Range(1, 1000000));
  o->add_option("--format", odo->format,
                "pose file format of both files (tum: poses are matched by line, times are not used)")
      ->check(CLI::IsMember({"kitti", "tum"}))
      ->capture_default_str();
  o->add_option("--json", odo->json_path, "write the results as JSON");
  o->add_option("--plot", odo->plot_path, "write a PNG (gnuplot): top view of both paths, errors per length");
  o->callback([odo, lengths, step] { run_odometry(*odo, lengths->count() > 0, step->count() > 0); });

  auto mos = std::make_shared<MosArgs>();
  auto* m = cmd->add_subcommand(
      "mos", "SemanticKITTI moving-object IoU over all points + object-level IoU (eq. 16)");
  m->add_option("GT_LABEL_DIR", mos->gt_dir, "folder of ground-truth NNNNNN.label files")->required();
  m->add_option("PRED_LABEL_DIR", mos->pred_dir, "folder with a predicted .label file for each one")
      ->required();
  m->add_option("--json", mos->json_path, "write the results as JSON");
  m->add_option("--object-threshold", mos->object_threshold,
                "an object is detected when more than this fraction of its points is predicted moving")
      ->check(CLI::Validator(
          [](const std::string& text) {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            const bool ok = end != text.c_str() && *end == '\0' && v >= 0.0 && v < 1.0;
            return ok ? std::string() : "must be a number in [0, 1), got " + text;
          },
          "in [0,1)"))
      ->capture_default_str();
  m->callback([mos] { run_mos(*mos); });

  auto map = std::make_shared<MapArgs>();
  auto* mp = cmd->add_subcommand(
      "map", "Static-map accuracy (DynamicMap benchmark style): SA, DA and their geometric mean");
  mp->footer(
      "The reference: every labelled point of SEQUENCE (labels/) placed with POSES (KITTI format, the frame "
      "of\n"
      "the sequence's poses.txt), in voxels of --leaf, dynamic where most points are moving. Each map point "
      "takes\n"
      "the nearest reference voxel within --radius. SA = static voxels kept, DA = dynamic voxels left out.\n"
      "Give the poses the map was built with (a run's poses.txt) so that map and reference line up.\n"
      "  dloam eval map out/0005/clean/map.ply ../shared/data/kitti-raw-0005 out/0005/poses.txt \\\n"
      "      --config config/kitti-raw.yaml --json map.json");
  mp->add_option("MAP", map->map, "map PLY (x y z)")->required()->check(CLI::ExistingFile);
  mp->add_option("SEQUENCE", map->sequence, "sequence folder with labels/")
      ->required()
      ->check(CLI::ExistingPath);
  mp->add_option("POSES", map->poses, "poses of the scans (KITTI)")->required()->check(CLI::ExistingFile);
  mp->add_option(
        "--config,-c", map->config_path,
        "the run's config (its config.yaml): the vertical-angle correction and de-skew of the reference")
      ->check(CLI::ExistingFile);
  mp->add_option("--leaf", map->eval.leaf, "reference voxel size (m)")->capture_default_str();
  mp->add_option("--radius", map->eval.radius, "match radius (m), at most --leaf")->capture_default_str();
  mp->add_option("--max-range", map->eval.max_range, "reference points within this of their scan (m)")
      ->capture_default_str();
  mp->add_option("--json", map->json_path, "write the results as JSON");
  mp->callback([map] { run_map(*map); });
}

}  // namespace dloam::app
