#include "html_report.hpp"

#include <fmt/core.h>
#include <nettle/base64.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#include "dloam/io/kitti.hpp"
#include "dloam/io/ply.hpp"
#include "gnuplot.hpp"

namespace dloam::app {

namespace {
namespace fs = std::filesystem;
using nlohmann::json;

/// Map points drawn at most (every k-th beyond it): gnuplot stays quick on long drives.
constexpr std::size_t kMaxMapPoints = 400000;
constexpr int kPlotWidth = 900;

std::string base64(const std::string& bytes) {
  std::string out(BASE64_ENCODE_RAW_LENGTH(bytes.size()), '\0');
  base64_encode_raw(out.data(), bytes.size(), reinterpret_cast<const std::uint8_t*>(bytes.data()));
  return out;
}

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// Gnuplot string literal in single quotes (a quote is doubled).
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string number(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  return fmt::format("{:.{}f}", v, digits);
}

/// metrics.json's `key` of `j` as a number: NaN when it is missing or null (JSON has no NaN: an
/// undefined value, e.g. the relative error of a path shorter than every segment, is written null).
double num(const json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : NAN;
}

/// metrics.json's count `key` of `j`, 0 when it is missing or null.
std::uint64_t count(const json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<std::uint64_t>() : 0;
}

/// What the report reads from the run folder.
struct Run {
  std::string dir;
  std::vector<Pose> poses, gt;  ///< sensor frame, anchored at the first scan
  std::vector<double> error;    ///< per scan: |position - ground truth| (m), when gt
  json metrics = json::object();
  PipelineConfig config;
  io::PlyCloud map, moving;
};

std::vector<Pose> anchored(std::vector<Pose> poses) {
  if (poses.empty()) return poses;
  const Pose first_inverse = poses.front().inverse();
  for (Pose& p : poses) p = first_inverse * p;
  return poses;
}

Run read_run(const std::string& dir) {
  Run r;
  r.dir = dir;
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  const auto require = [&](const char* name) {
    if (!fs::exists(file(name)))
      throw InputError(file(name) + ": missing (is " + dir + " a `dloam run` folder?)");
  };
  require("poses.txt");
  require("timing.csv");
  require("config.yaml");
  r.config = io::load_config(file("config.yaml"));
  std::optional<Pose> Tr;
  if (fs::exists(file("calib.txt"))) {
    const io::Calib calib = io::read_calib(file("calib.txt"));
    if (calib.has_Tr) Tr = calib.Tr;
  }
  const auto sensor_frame = [&](const std::vector<Pose>& poses) {
    return anchored(Tr ? io::camera_to_lidar(poses, *Tr) : poses);
  };
  r.poses = sensor_frame(io::read_kitti_poses(file("poses.txt")));
  if (fs::exists(file("poses_gt.txt"))) {
    r.gt = sensor_frame(io::read_kitti_poses(file("poses_gt.txt")));
    if (r.gt.size() != r.poses.size())
      throw InputError(file("poses_gt.txt") + ": " + std::to_string(r.gt.size()) + " poses, poses.txt has " +
                       std::to_string(r.poses.size()));
    for (std::size_t i = 0; i < r.poses.size(); ++i)
      r.error.push_back((r.poses[i].translation() - r.gt[i].translation()).norm());
  }
  if (fs::exists(file("metrics.json"))) {
    try {
      r.metrics = json::parse(io::read_file(file("metrics.json")));
    } catch (const json::exception& e) {
      throw InputError(file("metrics.json") + ": " + e.what());
    }
  }
  if (fs::exists(file("map.ply"))) r.map = io::read_ply(file("map.ply"));
  if (fs::exists(file("moving.ply"))) r.moving = io::read_ply(file("moving.ply"));
  return r;
}

/// Renders one plot into a PNG in `tmp` and returns it as a data URI.
class Plotter {
 public:
  explicit Plotter(fs::path tmp) : tmp_(std::move(tmp)) { fs::create_directories(tmp_); }
  ~Plotter() {
    std::error_code ec;
    fs::remove_all(tmp_, ec);
  }
  Plotter(const Plotter&) = delete;
  Plotter& operator=(const Plotter&) = delete;

  /// A data file in the temporary folder.
  [[nodiscard]] std::string data_file(const std::string& name) const { return (tmp_ / name).string(); }

  /// `body`: the script after `set terminal` / `set output`.
  std::string png(const std::string& name, int width, int height, const std::string& body) {
    const std::string path = (tmp_ / (name + ".png")).string();
    render_png(
        path,
        [&](const std::string& out, const std::string& terminal) {
          return fmt::format(
              "set terminal {} size {},{} noenhanced font ',11'\nset output {}\n{}\nset output\n", terminal,
              width, height, quoted(out), body);
        },
        /*announce=*/false);
    return "data:image/png;base64," + base64(io::read_file(path));
  }

 private:
  fs::path tmp_;
};

void write_points(const std::string& path, const std::vector<Vec3>& points, std::size_t max_points) {
  std::ofstream out(path);
  const std::size_t step = std::max<std::size_t>(1, (points.size() + max_points - 1) / max_points);
  char line[96];
  for (std::size_t i = 0; i < points.size(); i += step) {
    std::snprintf(line, sizeof(line), "%.3f %.3f %.3f\n", points[i].x(), points[i].y(), points[i].z());
    out << line;
  }
}

std::string trajectory_plot(Plotter& plot, const Run& r) {
  {
    std::ofstream out(plot.data_file("trajectory.dat"));
    for (std::size_t i = 0; i < r.poses.size(); ++i) {
      const Vec3 t = r.poses[i].translation();
      out << t.x() << ' ' << t.y() << ' ' << (r.error.empty() ? 0.0 : r.error[i]) << '\n';
    }
  }
  std::string body =
      "set size ratio -1\nset grid\nset key top left box opaque\nset xlabel 'x [m]'\nset ylabel 'y [m]'\n";
  if (r.gt.empty()) {
    body += "set title 'trajectory (top view, sensor frame of the first scan); no ground truth'\n";
    body += fmt::format("plot {} using 1:2 with lines lw 3 lc rgb '#1f77b4' title 'estimate'\n",
                        quoted(plot.data_file("trajectory.dat")));
  } else {
    {
      std::ofstream out(plot.data_file("gt.dat"));
      for (const Pose& p : r.gt) out << p.translation().x() << ' ' << p.translation().y() << '\n';
    }
    const double max_error = *std::max_element(r.error.begin(), r.error.end());
    body +=
        "set title 'trajectory (top view): estimate coloured by its position error, ground truth in grey'\n";
    body +=
        "set palette defined (0 '#2c7bb6', 0.5 '#fdae61', 1 '#d7191c')\nset cblabel 'position error [m]'\n";
    body += fmt::format("set cbrange [0:{}]\n", std::max(max_error, 1e-3));
    body += fmt::format(
        "plot {} using 1:2 with lines lw 6 lc rgb '#b0b0b0' title 'ground truth', \\\n"
        "     {} using 1:2:3 with lines lw 3 lc palette title 'estimate', \\\n"
        "     {} every ::0::0 using 1:2 with points pt 5 ps 2 lc rgb 'black' title 'start'\n",
        quoted(plot.data_file("gt.dat")), quoted(plot.data_file("trajectory.dat")),
        quoted(plot.data_file("trajectory.dat")));
  }
  return plot.png("trajectory", kPlotWidth, 760, body);
}

std::string relative_error_plot(Plotter& plot, const Run& r) {
  std::string body = "set grid\nset style fill solid 0.7\nset boxwidth 0.6\nset yrange [0:*]\nunset key\n";
  // The segment lengths with at least one segment.
  json measured = json::array();
  if (r.metrics.contains("odometry") && r.metrics["odometry"].contains("per_length"))
    for (const json& e : r.metrics["odometry"]["per_length"])
      if (count(e, "segments") > 0 && std::isfinite(num(e, "t_rel_pct"))) measured.push_back(e);
  const json* per_length = measured.empty() ? nullptr : &measured;
  if (!per_length) {
    body += "set title 'relative error per segment length'\n";
    body += fmt::format("set label 1 {} at graph 0.5,0.5 center\n",
                        quoted(r.gt.empty() ? "no ground truth: no relative error"
                                            : "no segment: the path is shorter than every segment length"));
    body += "plot [0:1] [0:1] NaN\n";
    return plot.png("relative-error", kPlotWidth, 460, body);
  }
  {
    std::ofstream out(plot.data_file("lengths.dat"));
    for (const json& e : *per_length)
      out << num(e, "length_m") << ' ' << num(e, "t_rel_pct") << ' ' << num(e, "r_rel_deg100m") << ' '
          << count(e, "segments") << '\n';
  }
  const std::string data = quoted(plot.data_file("lengths.dat"));
  body += fmt::format(
      "set multiplot layout 1,2 title 'KITTI devkit relative error per segment length'\n"
      "set xrange [-0.5:{}]\nset xlabel 'segment length [m]'\n",
      static_cast<double>(per_length->size()) - 0.5);
  body +=
      fmt::format("set ylabel 't_rel [%]'\nplot {} using 0:2:xtic(1) with boxes lc rgb '#1f77b4'\n", data);
  body += fmt::format(
      "set ylabel 'r_rel [deg/100 m]'\nplot {} using 0:3:xtic(1) with boxes lc rgb '#ff7f0e'\n", data);
  body += "unset multiplot\n";
  return plot.png("relative-error", kPlotWidth, 460, body);
}

std::string map_plot(Plotter& plot, const Run& r) {
  std::vector<Vec3> map = r.map.cloud.xyz;
  std::string body =
      "set size ratio -1\nset grid front\nset xlabel 'x [m]'\nset ylabel 'y [m]'\n"
      "set key top left box opaque\nset cblabel 'height z [m]'\n"
      "set palette defined (0 '#313695', 0.35 '#4575b4', 0.5 '#abd9e9', 0.65 '#fee090', "
      "0.8 '#f46d43', 1 '#a50026')\n";
  if (map.empty()) {
    body +=
        "set title 'global map: no map.ply'\nset label 1 'no map points' at graph 0.5,0.5 center\n"
        "plot [0:1] [0:1] NaN\n";
    return plot.png("map", kPlotWidth, 760, body);
  }
  // Colour range: the 2nd to 98th percentile of the heights, so a few outliers do not flatten it.
  std::vector<double> z;
  for (const Vec3& p : map) z.push_back(p.z());
  std::sort(z.begin(), z.end());
  const double lo = z[z.size() * 2 / 100], hi = z[std::min(z.size() - 1, z.size() * 98 / 100)];
  write_points(plot.data_file("map.dat"), map, kMaxMapPoints);
  write_points(plot.data_file("moving.dat"), r.moving.cloud.xyz, kMaxMapPoints);
  {
    std::ofstream out(plot.data_file("path.dat"));
    for (const Pose& p : r.poses) out << p.translation().x() << ' ' << p.translation().y() << '\n';
  }
  body += fmt::format("set cbrange [{}:{}]\n", lo, hi > lo ? hi : lo + 1.0);
  body += fmt::format(
      "set title 'global map from above ({} points), coloured by height; {} moving points in "
      "magenta'\n",
      map.size(), r.moving.cloud.size());
  body += fmt::format("plot {} using 1:2:3 with dots lc palette notitle", quoted(plot.data_file("map.dat")));
  if (!r.moving.cloud.empty())
    body += fmt::format(", \\\n     {} using 1:2 with points pt 7 ps 0.35 lc rgb '#e7298a' title 'moving'",
                        quoted(plot.data_file("moving.dat")));
  body += fmt::format(", \\\n     {} using 1:2 with lines lw 2 lc rgb 'black' title 'trajectory'\n",
                      quoted(plot.data_file("path.dat")));
  return plot.png("map", kPlotWidth, 760, body);
}

std::string timing_plot(Plotter& plot, const Run& r) {
  const std::string csv = quoted((fs::path(r.dir) / "timing.csv").string());
  // Columns 2..9: deskew, segmentation, step_check, detection, features, odometry, mapping, total.
  const std::string body = fmt::format(
      "set datafile separator ','\nset grid\nset key outside right top\nset xlabel 'scan'\n"
      "set ylabel 'time [ms]'\nset yrange [0:*]\n"
      "set title 'time per scan and pipeline module (mapping runs on a worker thread)'\n"
      "plot for [c=2:8] {0} using 1:c with lines lw 1.5 title columnheader(c), \\\n"
      "     {0} using 1:9 with lines lw 3 lc rgb 'black' title columnheader(9)\n",
      csv);
  return plot.png("timing", kPlotWidth, 460, body);
}

void table_row(std::ostringstream& html, const std::string& name, const std::string& value) {
  html << "<tr><th>" << escape(name) << "</th><td>" << escape(value) << "</td></tr>\n";
}

std::string tables(const Run& r) {
  std::ostringstream html;
  const json& m = r.metrics;
  html << "<section class=\"tables\">\n";
  html << "<div><h2>Odometry</h2><table>\n";
  if (m.contains("odometry")) {
    const json& o = m["odometry"];
    table_row(html, "frames", std::to_string(count(o, "frames")));
    table_row(html, "ground-truth path", number(num(o, "path_length_m"), 2) + " m");
    table_row(html, "t_rel (KITTI devkit)", number(num(o, "t_rel_pct"), 3) + " %");
    table_row(html, "r_rel", number(num(o, "r_rel_deg100m"), 3) + " deg/100 m");
    table_row(html, "ATE",
              number(num(o, "ate_m"), 3) + " m (aligned " + number(num(o, "ate_aligned_m"), 3) + " m)");
    table_row(html, "RPE per frame",
              number(num(o, "rpe_trans_m"), 4) + " m, " + number(num(o, "rpe_rot_deg"), 4) + " deg");
  } else {
    table_row(html, "ground truth", "none (no poses.txt in the input)");
  }
  html << "</table></div>\n";

  html << "<div><h2>Moving objects (MOS)</h2><table id=\"mos\">\n";
  if (m.contains("mos")) {
    const json& s = m["mos"];
    const auto pct = [&](const char* key) { return number(100.0 * num(s, key), 1) + " %"; };
    table_row(html, "scans", std::to_string(count(s, "scans")));
    table_row(html, "point IoU", pct("iou"));
    table_row(html, "precision / recall", pct("precision") + " / " + pct("recall"));
    table_row(html, "static IoU", pct("static_iou"));
    table_row(html, "TP / FP / FN",
              fmt::format("{} / {} / {}", count(s, "tp"), count(s, "fp"), count(s, "fn")));
    table_row(html, "object IoU (eq. 16)", pct("object_iou"));
    table_row(
        html, "objects TP / FP / FN",
        fmt::format("{} / {} / {}", count(s, "object_tp"), count(s, "object_fp"), count(s, "object_fn")));
  } else {
    table_row(html, "MOS",
              r.config.detection.detector == Detector::kNone ? "no detector in this run"
                                                             : "no ground-truth labels in the input");
  }
  if (m.contains("map_input_moving_fraction"))
    table_row(html, "moving points sent to the map",
              number(100.0 * num(m, "map_input_moving_fraction"), 3) + " %");
  if (m.contains("effective_feature_ratio"))
    table_row(html, "features on static points (Table III)",
              number(100.0 * num(m, "effective_feature_ratio"), 2) + " %");
  html << "</table></div>\n";

  html << "<div><h2>Run</h2><table>\n";
  table_row(html, "sensor",
            r.config.sensor.preset +
                fmt::format(" ({} x {})", r.config.sensor.N_scan, r.config.sensor.Horizon_SCAN));
  table_row(html, "detector", std::string(name_of(r.config.detection.detector)));
  table_row(html, "de-skew",
            r.config.deskew.enabled ? std::string(name_of(r.config.deskew.time_source)) : "off");
  table_row(html, "scans", std::to_string(r.poses.size()));
  table_row(html, "map points", std::to_string(r.map.cloud.size()));
  if (m.contains("loop_closures"))
    table_row(html, "loop closures", std::to_string(count(m, "loop_closures")));
  if (m.contains("tracking")) {
    const json& t = m["tracking"];
    table_row(html, "steps re-initialised / lost",
              fmt::format("{} / {}", count(t, "reinitialized_steps"), count(t, "lost_steps")));
    table_row(html, "gaps in the scan times", std::to_string(count(t, "gaps")));
    table_row(html, "scans without detection (step fitted too poorly)",
              std::to_string(count(t, "detection_suspended_scans")));
  }
  html << "</table></div>\n</section>\n";
  return html.str();
}

std::string figure(const char* id, const std::string& title, const std::string& uri) {
  return fmt::format(
      "<figure class=\"plot\" id=\"{}\"><img alt=\"{}\" src=\"{}\"><figcaption>{}</figcaption>"
      "</figure>\n",
      id, escape(title), uri, escape(title));
}

}  // namespace

void write_html_report(const std::string& run_dir, const std::string& html_path) {
  const Run r = read_run(run_dir);
  Plotter plot(fs::temp_directory_path() / fmt::format("dloam-report-{}", ::getpid()));
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>dloam report: "
       << escape(fs::path(run_dir).filename().string()) << "</title>\n"
       << "<style>\n"
          "body{font-family:sans-serif;margin:16px 24px;color:#222;background:#fff}\n"
          "h1{font-size:22px;margin:0 0 4px}h2{font-size:16px;margin:8px 0}\n"
          ".plots{display:grid;grid-template-columns:repeat(auto-fit,minmax(560px,1fr));gap:12px}\n"
          "figure.plot{margin:0;border:1px solid #ddd;padding:6px}\n"
          "figure.plot img{width:100%;height:auto;display:block}\n"
          "figcaption{font-size:13px;color:#555;margin-top:4px}\n"
          ".tables{display:grid;grid-template-columns:repeat(auto-fit,minmax(320px,1fr));gap:12px;margin-top:"
          "12px}\n"
          "table{border-collapse:collapse;font-size:14px;width:100%}\n"
          "th,td{border-bottom:1px solid #e4e4e4;padding:3px "
          "8px;text-align:left}th{font-weight:normal;color:#555}\n"
          "</style></head><body>\n";
  html << "<h1>dloam run: " << escape(run_dir) << "</h1>\n";
  html << "<p>" << r.poses.size() << " scans, sensor " << escape(r.config.sensor.preset) << ", detector "
       << name_of(r.config.detection.detector) << ".</p>\n";
  html << "<section class=\"plots\">\n";
  html << figure("trajectory", "Trajectory, top view", trajectory_plot(plot, r));
  html << figure("relative-error", "Relative error per segment length", relative_error_plot(plot, r));
  html << figure("map", "Global map, coloured by height; moving points marked", map_plot(plot, r));
  html << figure("timing", "Time per scan and module", timing_plot(plot, r));
  html << "</section>\n";
  html << tables(r);
  html << "</body></html>\n";
  io::write_atomic(html_path, [&](std::ostream& out) { out << html.str(); });
  fmt::print("wrote {}\n", html_path);
}

}  // namespace dloam::app
