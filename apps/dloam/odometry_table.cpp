#include "report.hpp"

#include <fmt/core.h>

#include "dloam/io/atomic_file.hpp"

namespace dloam::app {

using nlohmann::json;

eval::SegmentOptions segment_options(const std::vector<Pose>& gt, const std::vector<double>& lengths,
                                     std::size_t step) {
  eval::SegmentOptions o;
  if (!lengths.empty()) {
    o.lengths = lengths;
    o.step = step > 0 ? step : 1;
  } else if (!gt.empty() && eval::trajectory_distances(gt).back() < 200.0) {
    o.lengths = {5, 10, 20, 30};
    o.step = step > 0 ? step : 1;
  } else if (step > 0) {
    o.step = step;
  }
  return o;
}

void print_odometry(const eval::OdometryResult& r, const std::string& frame) {
  fmt::print("odometry: {} frames, ground-truth path {:.2f} m, frame: {}\n", r.frames, r.path_length_m,
             frame);
  fmt::print("  {:>10} {:>9} {:>12} {:>16}\n", "length [m]", "segments", "t_rel [%]", "r_rel [deg/100m]");
  for (const auto& e : r.relative.per_length)
    fmt::print("  {:>10g} {:>9} {:>12.4f} {:>16.4f}\n", e.length, e.count, e.t_rel_pct, e.r_rel_deg100m);
  fmt::print("  {:>10} {:>9} {:>12.4f} {:>16.4f}\n", "all", r.relative.segments.size(), r.relative.t_rel_pct,
             r.relative.r_rel_deg100m);
  if (r.relative.segments.empty())
    fmt::print("  no segment: the path is shorter than every segment length (try --lengths 5,10,20,30)\n");
  fmt::print("  ATE RMSE {:.4f} m (max {:.4f}), after SE(3) alignment {:.4f} m (max {:.4f})\n", r.ate.rmse,
             r.ate.max, r.ate_aligned.rmse, r.ate_aligned.max);
  fmt::print(
      "  RPE per frame: translation RMSE {:.4f} m (mean {:.4f}), rotation RMSE {:.4f} deg (mean {:.4f})\n",
      r.rpe.trans_m.rmse, r.rpe.trans_m.mean, r.rpe.rot_deg.rmse, r.rpe.rot_deg.mean);
}

json odometry_json(const eval::OdometryResult& r, const eval::SegmentOptions& options,
                   const std::string& frame) {
  json per_length = json::array();
  for (const auto& e : r.relative.per_length)
    per_length.push_back({{"length_m", e.length},
                          {"segments", e.count},
                          {"t_rel_pct", e.t_rel_pct},
                          {"r_rel_deg100m", e.r_rel_deg100m}});
  return {{"frame", frame},
          {"frames", r.frames},
          {"path_length_m", r.path_length_m},
          {"lengths_m", options.lengths},
          {"step", options.step},
          {"segments", r.relative.segments.size()},
          {"t_rel_pct", r.relative.t_rel_pct},
          {"r_rel_deg100m", r.relative.r_rel_deg100m},
          {"per_length", per_length},
          {"ate_m", r.ate.rmse},
          {"ate_max_m", r.ate.max},
          {"ate_aligned_m", r.ate_aligned.rmse},
          {"ate_aligned_max_m", r.ate_aligned.max},
          {"rpe_trans_m", r.rpe.trans_m.rmse},
          {"rpe_trans_mean_m", r.rpe.trans_m.mean},
          {"rpe_rot_deg", r.rpe.rot_deg.rmse},
          {"rpe_rot_mean_deg", r.rpe.rot_deg.mean}};
}

void write_odometry_metrics(const std::string& json_path, const std::vector<Pose>& gt,
                            const std::vector<Pose>& est, const std::vector<double>& lengths) {
  const auto options = segment_options(gt, lengths);
  const auto r = eval::evaluate_odometry(gt, est, options);
  const std::string frame = "lidar";
  print_odometry(r, frame);
  const json doc = {{"odometry", odometry_json(r, options, frame)}};
  io::write_atomic(json_path, [&](std::ostream& out) { out << doc.dump(2) << '\n'; });
  fmt::print("wrote {}\n", json_path);
}

}  // namespace dloam::app
