// Sensor model: beam table, row search from each beam's origin (eq. 4 with a beam table).
#include "dloam/core/sensor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dloam {

double SensorConfig::beam_elevation_deg(int row) const {
  if (!beam_elevations_deg.empty()) return beam_elevations_deg[static_cast<std::size_t>(row)];
  if (N_scan <= 1) return Pit_bottom;
  return Pit_bottom + (fov_top - Pit_bottom) * row / (N_scan - 1);
}

double SensorConfig::beam_vertical_offset_m(int row) const {
  return beam_vertical_offsets_m.empty() ? 0.0 : beam_vertical_offsets_m[static_cast<std::size_t>(row)];
}

int SensorConfig::row_of_point(const Vec3& p) const { return BeamLookup(*this).row(p); }

int SensorConfig::row_of_elevation(double e) const {
  if (N_scan <= 1) return 0;
  if (beam_elevations_deg.empty()) {
    const double R_vert = (fov_top - Pit_bottom) / (N_scan - 1);
    const double v = std::round((e - Pit_bottom) / R_vert);  // paper eq. 4
    if (v < -0.5 || v > N_scan - 0.5 || std::isnan(v)) return -1;
    return std::clamp(static_cast<int>(v), 0, N_scan - 1);
  }
  const auto& b = beam_elevations_deg;
  auto it = std::lower_bound(b.begin(), b.end(), e);
  int hi = static_cast<int>(it - b.begin());
  int row;
  if (hi == 0) {
    row = 0;
  } else if (hi == N_scan) {
    row = N_scan - 1;
  } else {
    row = (e - b[static_cast<std::size_t>(hi - 1)] < b[static_cast<std::size_t>(hi)] - e) ? hi - 1 : hi;
  }
  // Outside the field of view by more than half the local spacing.
  const double spacing_lo = b[1] - b[0];
  const double spacing_hi = b[b.size() - 1] - b[b.size() - 2];
  if (e < b.front() - 0.5 * spacing_lo || e > b.back() + 0.5 * spacing_hi) return -1;
  return row;
}

void SensorConfig::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("sensor: " + what); };
  if (N_scan < 2 || N_scan > 512) fail("N_scan must be in [2, 512], got " + std::to_string(N_scan));
  if (Horizon_SCAN < 16 || Horizon_SCAN > 16384)
    fail("Horizon_SCAN must be in [16, 16384], got " + std::to_string(Horizon_SCAN));
  if (!beam_elevations_deg.empty()) {
    for (const double e : beam_elevations_deg)
      if (!(std::abs(e) < 89.0))
        fail("beam_elevations_deg must lie in (-89, 89) deg, got " + std::to_string(e));
    if (static_cast<int>(beam_elevations_deg.size()) != N_scan)
      fail("beam_elevations_deg has " + std::to_string(beam_elevations_deg.size()) +
           " entries but N_scan is " + std::to_string(N_scan));
    if (!std::is_sorted(beam_elevations_deg.begin(), beam_elevations_deg.end()) ||
        std::adjacent_find(beam_elevations_deg.begin(), beam_elevations_deg.end()) !=
            beam_elevations_deg.end())
      fail("beam_elevations_deg must be strictly increasing (bottom beam first)");
  } else if (!(fov_top > Pit_bottom)) {
    fail("fov_top must be above Pit_bottom");
  }
  if (!beam_vertical_offsets_m.empty()) {
    if (static_cast<int>(beam_vertical_offsets_m.size()) != N_scan)
      fail("beam_vertical_offsets_m has " + std::to_string(beam_vertical_offsets_m.size()) +
           " entries but N_scan is " + std::to_string(N_scan));
    for (const double dz : beam_vertical_offsets_m)
      if (!(std::abs(dz) <= 1.0))
        fail("beam_vertical_offsets_m must lie in [-1, 1] m, got " + std::to_string(dz));
  }
  if (!(min_range >= 0.0) || !(max_range > min_range)) fail("need 0 <= min_range < max_range");
  if (!(scan_rate_hz > 0.0)) fail("scan_rate_hz must be positive");
}

BeamLookup::BeamLookup(const SensorConfig& s) : rows_(s.N_scan) {
  constexpr double kDeg = M_PI / 180.0;
  auto tan_of = [&](double deg) { return std::tan(std::clamp(deg, -89.5, 89.5) * kDeg); };
  const double e0 = s.beam_elevation_deg(0), e1 = s.beam_elevation_deg(1);
  const double top = s.beam_elevation_deg(rows_ - 1), below_top = s.beam_elevation_deg(rows_ - 2);
  bound_.push_back(tan_of(e0 - 0.5 * (e1 - e0)));
  for (int k = 0; k < rows_; ++k) {
    const double e = s.beam_elevation_deg(k);
    beam_tan_.push_back(tan_of(e));
    bound_.push_back(k + 1 < rows_ ? tan_of(0.5 * (e + s.beam_elevation_deg(k + 1)))
                                   : tan_of(top + 0.5 * (top - below_top)));
  }
  for (const double dz : s.beam_vertical_offsets_m)
    if (dz != 0.0) offset_ = s.beam_vertical_offsets_m;
  // Band at the lower edge of each of kBins equal bins of tan(elevation): one or two steps from
  // there find the band, instead of a binary search (the speed matrix locates every point).
  constexpr int kBins = 8192;
  scale_ = kBins / (bound_.back() - bound_.front());
  first_band_.resize(kBins);
  int k = 0;
  for (int b = 0; b < kBins; ++b) {
    while (k + 1 < rows_ && bound_.front() + b / scale_ >= bound_[static_cast<std::size_t>(k) + 1]) ++k;
    first_band_[static_cast<std::size_t>(b)] = k;
  }
}

int BeamLookup::band(double t) const {
  if (!(t >= bound_.front())) return -1;  // also NaN
  if (t >= bound_.back()) return rows_;
  const auto bin = std::min(static_cast<std::size_t>((t - bound_.front()) * scale_), first_band_.size() - 1);
  int k = first_band_[bin];
  while (t >= bound_[static_cast<std::size_t>(k) + 1]) ++k;  // the bin can start in a lower band
  return k;
}

int BeamLookup::row(const Vec3& p) const {
  int r = -1, neighbour = -1;
  return locate(p, r, neighbour) ? r : -1;
}

bool BeamLookup::locate(const Vec3& p, int& row, int& neighbour) const {
  const double h = std::sqrt(p.x() * p.x() + p.y() * p.y());
  if (!(h > 0.0) || !std::isfinite(p.z())) return false;
  const double inv_h = 1.0 / h;
  auto offset = [&](int b) {
    return offset_.empty() ? 0.0 : offset_[static_cast<std::size_t>(std::clamp(b, 0, rows_ - 1))];
  };
  // Seen from the sensor origin, a near point can be a few bands above its beam: start from the
  // bottom beam's origin and look again from the origin of the beam found until the band is that
  // beam's own (1-2 steps; between two blocks of different heights the last one found is kept).
  int k = band((p.z() - offset(0)) * inv_h);
  for (int step = 0; step < 8 && !offset_.empty(); ++step) {
    const int next = band((p.z() - offset(k)) * inv_h);
    if (next == k) break;
    k = next;
  }
  if (k < 0 || k >= rows_) return false;
  row = k;
  const bool above = (p.z() - offset(k)) * inv_h > beam_tan_[static_cast<std::size_t>(k)];
  neighbour = std::clamp(above ? k + 1 : k - 1, 0, rows_ - 1);
  return true;
}

}  // namespace dloam
