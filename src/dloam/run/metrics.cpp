#include "dloam/run/metrics.hpp"

#include <algorithm>
#include <map>
#include <string>

namespace dloam::run {

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
          {"rpe_rot_mean_deg", r.rpe.rot_deg.mean},
          {"steps", r.rpe.steps},
          {"steps_tracked", r.rpe.tracked}};
}

json mos_json(const eval::MosResult& r, double object_threshold) {
  const auto& p = r.points;
  const auto& o = r.objects;
  return {{"scans", r.scans},
          {"iou", p.iou()},
          {"precision", p.precision()},
          {"recall", p.recall()},
          {"static_iou", p.static_iou()},
          {"tp", p.tp},
          {"fp", p.fp},
          {"fn", p.fn},
          {"tn", p.tn},
          {"ignored", p.ignored},
          {"object_iou", o.iou()},
          {"object_tp", o.tp},
          {"object_fp", o.fp},
          {"object_fn", o.fn},
          {"object_threshold", object_threshold}};
}

void LabelStats::add(const std::vector<Label>& gt, const ScanResult& r) {
  std::vector<std::size_t> idx = r.edge_features;
  idx.insert(idx.end(), r.plane_features.begin(), r.plane_features.end());
  features += eval::count_effective_features(gt, idx);
  for (std::size_t i : r.map_points) {
    if (semantic::is_ignored(gt[i])) continue;
    ++map_points;
    map_moving += semantic::is_moving(gt[i]);
  }
  if (!r.labels.empty()) {
    detector = true;
    eval::add_scan(mos, gt, r.labels);
  }
}

json LabelStats::json() const {
  nlohmann::json j = {{"effective_feature_ratio", features.ratio()},
                      {"features_on_labelled_points", features.total},
                      {"map_input_moving_fraction", map_moving_fraction()}};
  if (detector) j["mos"] = mos_json(mos);
  return j;
}

json tracking_json(const std::vector<ScanResult>& results) {
  std::size_t gaps = 0, missed = 0, degenerate = 0, map_degenerate = 0, searched = 0, reinitialized = 0,
              suspended = 0;
  // Per axis: scans with an unconstrained direction mostly along it (odometry, scan-to-map).
  std::map<std::string, std::size_t> axes, map_axes;
  auto count_axes = [](const Degeneracy& d, std::map<std::string, std::size_t>& into) {
    for (int a = 0; a < d.unconstrained; ++a) ++into[direction_name(d.eigenvectors.col(a))];
  };
  std::vector<std::size_t> lost;
  double max_dt = 0.0;
  for (const ScanResult& r : results) {
    gaps += r.missed_scans > 0;
    missed += static_cast<std::size_t>(r.missed_scans);
    degenerate += r.degenerate;
    map_degenerate += r.map_degeneracy.degenerate();
    if (r.degenerate) count_axes(r.degeneracy, axes);
    count_axes(r.map_degeneracy, map_axes);
    searched += r.search_candidates > 0;
    reinitialized += r.reinitialized;
    suspended += r.detection_suspended;
    if (r.lost) lost.push_back(r.index);
    max_dt = std::max(max_dt, r.dt);
  }
  return {{"scans", results.size()},
          {"gaps", gaps},
          {"missed_scans", missed},
          {"max_interval_s", max_dt},
          {"searched_steps", searched},
          {"reinitialized_steps", reinitialized},
          {"lost_steps", lost.size()},
          {"lost_scans", lost},
          {"detection_suspended_scans", suspended},
          {"degenerate_scans", degenerate},
          {"unconstrained_axes", axes},
          {"map_degenerate_scans", map_degenerate},
          {"map_unconstrained_axes", map_axes}};
}

}  // namespace dloam::run
