// Sensor guess from the elevation histogram: field of view and beam peaks vs the presets.
#include "dloam/io/sensor_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dloam/core/preprocess.hpp"
#include "dloam/core/sensor.hpp"

namespace dloam::io {

void ElevationHistogram::add(const PointCloud& cloud, double min_range) {
  for (const auto& p : cloud.xyz) {
    const double r = std::hypot(p.x(), p.y());
    if (r < min_range) continue;
    const double e = std::atan2(p.z(), r) * 180.0 / M_PI;
    const auto bin = static_cast<std::size_t>(std::clamp((e + 90.0) / bin_deg, 0.0, counts.size() - 1.0));
    ++counts[bin];
    ++total;
  }
}

double ElevationHistogram::quantile(double q) const {
  const double target = q * static_cast<double>(total);
  double sum = 0.0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    sum += static_cast<double>(counts[i]);
    if (sum >= target) return -90.0 + (static_cast<double>(i) + 0.5) * bin_deg;
  }
  return 90.0;
}

namespace {
/// Peaks of the [1 2 1]-smoothed histogram: bins that are the maximum within +-2 bins and
/// rise clearly (by a quarter) above the lowest bin on each side before the next peak.
int count_peaks(const std::vector<std::size_t>& counts) {
  const std::size_t n = counts.size();
  std::vector<double> s(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i)
    s[i] = 0.25 * static_cast<double>(counts[i - 1] + 2 * counts[i] + counts[i + 1]);
  const double floor_level = 1e-4 * *std::max_element(s.begin(), s.end());
  int peaks = 0;
  double valley = 0.0;    // lowest value since the last accepted peak
  double candidate = -1;  // current peak height waiting for its right-hand valley
  for (std::size_t i = 2; i + 2 < n; ++i) {
    const bool local_max =
        s[i] > floor_level && s[i] >= s[i - 1] && s[i] >= s[i - 2] && s[i] > s[i + 1] && s[i] >= s[i + 2];
    if (candidate < 0) {
      valley = std::min(valley, s[i]);
      if (local_max && s[i] > 1.25 * valley + floor_level) candidate = s[i];
    } else {
      candidate = std::max(candidate, s[i]);
      if (s[i] < 0.8 * candidate) {  // fell clearly after the peak: accept it
        ++peaks;
        candidate = -1;
        valley = s[i];
      }
    }
  }
  return peaks + (candidate >= 0 ? 1 : 0);
}
}  // namespace

SensorEstimate estimate_sensor(const ElevationHistogram& h) {
  if (h.total == 0) throw InputError("sensor estimate: no points farther than the minimum range");
  SensorEstimate est;
  est.lowest_deg = h.quantile(0.0005);
  est.highest_deg = h.quantile(0.9995);
  est.resolved_beams = count_peaks(h.counts);
  double best = -1.0;
  for (const auto& name : sensor_preset_names()) {
    const SensorConfig s = sensor_preset(name);
    const double lo = s.beam_elevation_deg(0), hi = s.beam_elevation_deg(s.N_scan - 1);
    const double inter = std::max(0.0, std::min(hi, est.highest_deg) - std::max(lo, est.lowest_deg));
    const double uni = std::max(hi, est.highest_deg) - std::min(lo, est.lowest_deg);
    const double overlap = uni > 0.0 ? inter / uni : 0.0;
    // Field of view decides; the beam count only separates presets with similar fields of view.
    const double beams = std::min(est.resolved_beams, s.N_scan) / static_cast<double>(s.N_scan);
    const double score = overlap + 0.1 * beams;
    if (score > best) {
      best = score;
      est.preset = s.preset;
      est.fov_overlap = overlap;
    }
  }
  return est;
}

SensorFit sensor_fit(const PointCloud& cloud, const SensorConfig& sensor) {
  SensorFit fit;
  fit.points = cloud.size();
  std::vector<Vec3> points = cloud.xyz;
  correct_vertical_angle(points, sensor.vertical_angle_correction_deg);
  const BeamLookup beams(sensor);  // the rows of the range image, beam origin heights included
  for (const auto& p : points) {
    const double r = p.norm();
    if (!(r >= sensor.min_range && r <= sensor.max_range)) continue;
    ++fit.in_range;
    fit.inside += beams.row(p) >= 0;
  }
  return fit;
}

std::string sensor_fit_problem(const SensorFit& fit, const SensorConfig& sensor, const std::string& file) {
  if (fit.in_range < kMinFitPoints || fit.inside >= 0.9 * static_cast<double>(fit.in_range)) return {};
  char pct[16];
  std::snprintf(pct, sizeof(pct), "%.0f",
                100.0 * static_cast<double>(fit.inside) / static_cast<double>(fit.in_range));
  char fov[64];
  std::snprintf(fov, sizeof(fov), "%.1f .. %.1f deg", sensor.beam_elevation_deg(0),
                sensor.beam_elevation_deg(sensor.N_scan - 1));
  return file + ": only " + pct +
         "% of the points lie inside the vertical field of view of the sensor model '" + sensor.preset +
         "' (" + std::to_string(sensor.N_scan) + " beams, " + fov +
         "): wrong --preset or sensor config? (`dloam check` estimates it)";
}

}  // namespace dloam::io
