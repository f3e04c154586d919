#include "odometry_table.hpp"

#include <fmt/core.h>

namespace dloam::app {

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
  if (r.rpe.steps > 0)
    fmt::print("  steps within {:g} cm and {:g} deg: {} of {} ({:.1f} %)\n", eval::kTrackedStepM * 100,
               eval::kTrackedStepDeg, r.rpe.tracked, r.rpe.steps, 100.0 * r.rpe.tracked / r.rpe.steps);
}

void print_mos(const eval::MosResult& r, double object_threshold) {
  const auto& p = r.points;
  const auto& o = r.objects;
  fmt::print("MOS: {} scans, {} points ({} ignored: ground truth unlabeled/outlier)\n", r.scans,
             p.tp + p.fp + p.fn + p.tn + p.ignored, p.ignored);
  fmt::print("  points   IoU {:.4f}  precision {:.4f}  recall {:.4f}  static IoU {:.4f}\n", p.iou(),
             p.precision(), p.recall(), p.static_iou());
  fmt::print("           TP {}  FP {}  FN {}  TN {}\n", p.tp, p.fp, p.fn, p.tn);
  fmt::print("  objects  IoU {:.4f}  TP {}  FP {}  FN {}  (detected: > {:g} % of points predicted moving)\n",
             o.iou(), o.tp, o.fp, o.fn, 100.0 * object_threshold);
}

}  // namespace dloam::app
