#include "dloam/run/scan_checks.hpp"

#include "dloam/io/sensor_estimate.hpp"

namespace dloam::run {

void SensorFitCheck::check(const PointCloud& cloud, const std::string& file) {
  if (done_) return;
  const io::SensorFit fit = io::sensor_fit(cloud, sensor_);
  const std::string problem = io::sensor_fit_problem(fit, sensor_, file);
  if (!problem.empty()) throw InputError(problem);
  done_ = fit.in_range >= io::kMinFitPoints;
}

std::string DegenerateScans::add(ScanResult& r, const PointCloud& cloud, std::size_t dropped,
                                 const std::string& file) {
  const bool first_scan = processed_ == 0;
  ++processed_;
  dropped_points_ += dropped;
  std::size_t usable = 0;
  for (const auto& p : cloud.xyz) {
    const double range = p.norm();
    usable += range > 0.0 && range >= sensor_.min_range && range <= sensor_.max_range;
  }
  const bool few = r.n_edges < kMinFeatures || r.n_planes < kMinFeatures;
  if (usable == 0) ++without_points_;
  if (usable > 0 && !few) return {};
  r.degenerate = true;
  scans_.push_back(r.index);
  later_ += !first_scan;
  if (scans_.size() > kListed) return {};
  const std::string why =
      usable == 0 ? "no point between min_range and max_range"
                  : std::to_string(r.n_edges) + " edge and " + std::to_string(r.n_planes) + " plane features";
  return file + ": degenerate scan (" + why + "); the predicted motion is kept" +
         (scans_.size() == kListed ? " (further degenerate scans are only counted)" : "");
}

nlohmann::json DegenerateScans::json() const {
  return {{"processed", processed_},
          {"degenerate", scans_.size()},
          {"degenerate_scans", scans_},
          {"without_usable_points", without_points_},
          {"dropped_no_return_points", dropped_points_}};
}

}  // namespace dloam::run
