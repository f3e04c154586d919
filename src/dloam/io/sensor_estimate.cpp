// Sensor model of a sequence: scans read, estimate, YAML section and summary lines.
#include "dloam/io/sensor_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dloam/core/preprocess.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/io/config_yaml.hpp"

namespace dloam::io {

namespace {
std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), fmt, a, b, c, d);
  return buf;
}
}  // namespace

std::vector<std::size_t> spread_scan_indices(std::size_t first, std::size_t last, std::size_t count) {
  std::vector<std::size_t> out;
  if (last <= first || count == 0) return out;
  const std::size_t n = last - first;
  const std::size_t k = std::min(n, count);
  for (std::size_t j = 0; j < k; ++j) out.push_back(first + j * n / k);
  return out;
}

InputError estimate_error(const std::string& source, const InputError& error) {
  return InputError(source + ": " + error.what());
}

SensorModelEstimate estimate_sequence_sensor(const Sequence& seq, const std::vector<std::size_t>& indices,
                                             const SensorEstimationConfig& config) {
  std::vector<std::vector<Vec3>> scans;
  for (const std::size_t i : indices) scans.push_back(seq.read_scan(i).xyz);
  try {
    return estimate_sensor_model(scans, seq.times, config);
  } catch (const InputError& e) {
    throw estimate_error(seq.dir, e);
  }
}

std::vector<std::string> describe_estimate(const SensorModelEstimate& est) {
  const SensorConfig& s = est.sensor;
  std::vector<std::string> lines;
  double min_gap = INFINITY, max_gap = 0.0;
  for (int k = 1; k < s.N_scan; ++k) {
    const double g = s.beam_elevation_deg(k) - s.beam_elevation_deg(k - 1);
    min_gap = std::min(min_gap, g);
    max_gap = std::max(max_gap, g);
  }
  lines.push_back(std::to_string(s.N_scan) + " beams, elevation " +
                  format("%.2f .. %.2f deg, spacing %.2f .. %.2f deg", s.beam_elevation_deg(0),
                         s.beam_elevation_deg(s.N_scan - 1), min_gap, max_gap) +
                  format(" (%.1f %% of the points on them)", 100.0 * est.on_beam_fraction));
  double lo = INFINITY, hi = -INFINITY;
  for (int k = 0; k < s.N_scan; ++k) {
    lo = std::min(lo, s.beam_vertical_offset_m(k));
    hi = std::max(hi, s.beam_vertical_offset_m(k));
  }
  lines.push_back(format("beam origin heights %.3f .. %.3f m", lo, hi));
  lines.push_back(std::to_string(s.Horizon_SCAN) + " columns" +
                  (est.azimuth_step_deg > 0.0 ? format(" (azimuth step %.4f deg = %.0f firings per turn)",
                                                       est.azimuth_step_deg, 360.0 / est.azimuth_step_deg)
                                              : std::string()) +
                  format(", range %.1f .. %.0f m, %.2f Hz", s.min_range, s.max_range, s.scan_rate_hz) +
                  (est.scan_rate_measured ? "" : " (assumed)"));
  if (s.vertical_angle_correction_deg != 0.0)
    lines.push_back(format("vertical_angle_correction_deg %.3f applied before estimating",
                           s.vertical_angle_correction_deg));
  const PresetMatch m = nearest_preset(s);
  lines.push_back((m.resembles ? "resembles preset " : "nearest preset ") + m.preset +
                  format(" (%.0f beams; mean elevation distance %.3f deg)", m.preset_beams, m.distance_deg) +
                  (m.resembles ? "" : ": no preset resembles it closely"));
  lines.push_back("from " + std::to_string(est.scans) + (est.scans == 1 ? " scan (" : " scans (") +
                  std::to_string(est.points_used) + " of " + std::to_string(est.points) + " points used)");
  for (const auto& note : est.notes) lines.push_back("note: " + note);
  return lines;
}

std::string estimated_sensor_yaml(const SensorModelEstimate& est, const std::string& source) {
  std::string head = "# Sensor model estimated by `dloam check --write-sensor` from " + source + ":\n";
  for (const auto& line : describe_estimate(est)) head += "#   " + line + "\n";
  head +=
      "# Use: dloam run SEQUENCE --config THIS_FILE. Sections for the rest of the pipeline (deskew:,\n"
      "# mapping:, ...) can be appended below.\n";
  PipelineConfig cfg;
  cfg.sensor = est.sensor;
  return head + dump_config(cfg, "sensor");
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
