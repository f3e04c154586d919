// Sensor model from the points: beams as modes of the elevation distribution (origin heights by
// local sharpness), robust per-beam line fits in (1/h, z/h), image width, range limits, scan rate.
#include "dloam/core/sensor_estimation.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "dloam/core/preprocess.hpp"

namespace dloam {

namespace {
constexpr double kDeg = M_PI / 180.0;
constexpr double kBinDeg = 0.01;          ///< elevation histogram bin
constexpr double kOffsetStep = 0.005;     ///< m, origin heights tried in the histogram search
constexpr double kWindowDeg = 1.5;        ///< half width of the neighbourhood whose sharpness picks dz
constexpr double kResidualFloor = 3e-5;   ///< rad: float32 coordinates of points tens of metres away
constexpr std::size_t kMinPoints = 2000;  ///< points needed at all
constexpr std::size_t kHoughPoints = 200000;
constexpr double kMinOnBeam = 0.8;  ///< fraction of the points the beams must explain
constexpr double kMaxSpread = 0.1;  ///< largest median beam rms / median beam spacing

[[noreturn]] void fail(const std::string& what) { throw InputError("sensor estimate: " + what); }

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

/// A point as the fit sees it: horizontal distance, height, azimuth.
struct Sample {
  float h, z, azimuth;
};

/// atan() by linear interpolation in a table over [lo, hi] (error below 1e-6 rad).
class AtanTable {
 public:
  AtanTable(double lo, double hi) : lo_(lo), step_(0.002) {
    const auto n = static_cast<std::size_t>(std::ceil((hi - lo) / step_)) + 2;
    v_.resize(n);
    for (std::size_t i = 0; i < n; ++i) v_[i] = std::atan(lo + step_ * static_cast<double>(i));
  }
  /// False outside the table.
  bool operator()(double t, double& out) const {
    const double x = (t - lo_) / step_;
    if (!(x >= 0.0) || x >= static_cast<double>(v_.size() - 1)) return false;
    const auto i = static_cast<std::size_t>(x);
    const double f = x - static_cast<double>(i);
    out = v_[i] + f * (v_[i + 1] - v_[i]);
    return true;
  }

 private:
  double lo_, step_;
  std::vector<double> v_;
};

/// Elevation histograms of points seen from heights dz on a grid, and the profile whose every bin
/// comes from the height that makes its neighbourhood sharpest.
struct OffsetHistograms {
  double e0 = 0.0;  ///< deg, lower edge of bin 0
  int bins = 0;
  std::vector<double> dz;
  std::vector<std::vector<float>> H;  ///< [dz][bin]
  std::vector<double> profile;        ///< counts
  std::vector<double> profile_dz;     ///< height chosen per bin
  double global_dz = 0.0;             ///< the sharpest single height

  [[nodiscard]] double elevation_of_bin(double b) const { return e0 + (b + 0.5) * kBinDeg; }
};

OffsetHistograms offset_histograms(const std::vector<Sample>& pts, double max_offset) {
  OffsetHistograms o;
  double lo = 90.0, hi = -90.0;
  for (const Sample& s : pts) {
    const double e = std::atan2(static_cast<double>(s.z), static_cast<double>(s.h)) / kDeg;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  // Seen from heights up to max_offset, a beam of points a few metres away lies a few degrees
  // lower or higher than seen from the origin.
  std::vector<float> h(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) h[i] = pts[i].h;
  const auto near = h.begin() + static_cast<std::ptrdiff_t>(h.size() / 20);
  std::nth_element(h.begin(), near, h.end());
  const double pad =
      std::clamp(std::atan(max_offset / std::max(0.1, static_cast<double>(*near))) / kDeg, 1.0, 20.0);
  lo = std::max(lo - pad, -88.0);
  hi = std::min(hi + pad, 88.0);
  o.e0 = lo;
  o.bins = static_cast<int>(std::ceil((hi - lo) / kBinDeg));
  for (double d = -max_offset; d <= max_offset + 1e-9; d += kOffsetStep) o.dz.push_back(d);
  const AtanTable atan_of(std::tan(lo * kDeg), std::tan(hi * kDeg));
  std::vector<float> u(pts.size()), tau(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    u[i] = 1.0f / pts[i].h;
    tau[i] = pts[i].z / pts[i].h;
  }
  o.H.assign(o.dz.size(), std::vector<float>(static_cast<std::size_t>(o.bins), 0.0f));
  const double to_bin = 1.0 / (kDeg * kBinDeg), lo_rad = lo * kDeg;
  tbb::parallel_for(std::size_t{0}, o.dz.size(), [&](std::size_t k) {
    std::vector<float>& row = o.H[k];
    const auto dz = static_cast<float>(o.dz[k]);
    for (std::size_t i = 0; i < u.size(); ++i) {
      double e = 0.0;
      if (!atan_of(tau[i] - dz * u[i], e)) continue;
      const double b = (e - lo_rad) * to_bin;
      if (b >= 0.0 && b < o.bins) row[static_cast<std::size_t>(b)] += 1.0f;
    }
  });
  // Sharpness of a neighbourhood: the count-weighted mean count of its bins, sum H^2 / sum H.
  const int w = static_cast<int>(std::lround(kWindowDeg / kBinDeg));
  const auto nb = static_cast<std::size_t>(o.bins);
  std::vector<std::vector<double>> s1(o.dz.size(), std::vector<double>(nb + 1, 0.0)), s2 = s1;
  double best_global = -1.0;
  for (std::size_t k = 0; k < o.dz.size(); ++k) {
    double a = 0.0, b = 0.0;
    for (std::size_t i = 0; i < nb; ++i) {
      const double c = o.H[k][i];
      a += c;
      b += c * c;
      s1[k][i + 1] = a;
      s2[k][i + 1] = b;
    }
    const double sharp = a > 0.0 ? b / a : 0.0;
    if (sharp > best_global) {
      best_global = sharp;
      o.global_dz = o.dz[k];
    }
  }
  o.profile.assign(nb, 0.0);
  o.profile_dz.assign(nb, o.global_dz);
  for (std::size_t i = 0; i < nb; ++i) {
    const std::size_t a = i > static_cast<std::size_t>(w) ? i - static_cast<std::size_t>(w) : 0;
    const std::size_t b = std::min(nb, i + static_cast<std::size_t>(w) + 1);
    std::vector<double> r(o.dz.size(), 0.0);
    double best = 0.0;
    for (std::size_t k = 0; k < o.dz.size(); ++k) {
      const double n = s1[k][b] - s1[k][a];
      r[k] = n >= 1.0 ? (s2[k][b] - s2[k][a]) / n : 0.0;
      best = std::max(best, r[k]);
    }
    // Among the heights nearly as sharp, the one nearest the global height: a neighbourhood of
    // beams whose points all lie at one distance (ground rings) is as sharp for any height.
    std::size_t chosen = static_cast<std::size_t>(std::min_element(o.dz.begin(), o.dz.end(),
                                                                   [&](double x, double y) {
                                                                     return std::abs(x - o.global_dz) <
                                                                            std::abs(y - o.global_dz);
                                                                   }) -
                                                  o.dz.begin());
    if (best > 0.0) {
      double nearest = INFINITY;
      for (std::size_t k = 0; k < o.dz.size(); ++k)
        if (r[k] >= 0.98 * best && std::abs(o.dz[k] - o.global_dz) < nearest) {
          nearest = std::abs(o.dz[k] - o.global_dz);
          chosen = k;
        }
    }
    o.profile_dz[i] = o.dz[chosen];
  }
  // The profile counts every point once, at its elevation seen from the height chosen where it
  // lies (a fixed point: two steps from the global height).
  for (const Sample& s : pts) {
    double dz = o.global_dz, e = 0.0;
    bool inside = false;
    for (int step = 0; step < 3; ++step) {
      if (!atan_of((s.z - dz) / s.h, e)) break;
      const double b = (e / kDeg - lo) / kBinDeg;
      inside = b >= 0.0 && b < o.bins;
      if (!inside) break;
      const double next = o.profile_dz[static_cast<std::size_t>(b)];
      if (step == 2 || next == dz) {
        o.profile[static_cast<std::size_t>(b)] += 1.0;
        break;
      }
      dz = next;
    }
  }
  return o;
}

struct Peak {
  double elevation_deg, offset_m, count;
};

/// Modes of the profile: local maxima (within +-0.03 deg) that stand out of the valleys on both
/// sides by 30 % of their height and hold at least `min_count` points.
std::vector<Peak> find_peaks(const OffsetHistograms& o, double min_count) {
  const std::vector<double>& p = o.profile;
  const std::size_t n = p.size();
  std::vector<double> s(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    s[i] = 0.5 * p[i] + 0.25 * ((i > 0 ? p[i - 1] : 0.0) + (i + 1 < n ? p[i + 1] : 0.0));
  std::vector<Peak> peaks;
  constexpr std::size_t kHalf = 3, kReach = 100;
  for (std::size_t i = kHalf; i + kHalf < n; ++i) {
    if (s[i] <= 0.0) continue;
    bool local = true;
    for (std::size_t j = i - kHalf; j <= i + kHalf && local; ++j) local = j < i ? s[j] < s[i] : s[j] <= s[i];
    if (!local) continue;
    double left = s[i], right = s[i];
    for (std::size_t j = i; j > 0 && i - j < kReach && s[j - 1] <= s[i]; --j) left = std::min(left, s[j - 1]);
    for (std::size_t j = i; j + 1 < n && j - i < kReach && s[j + 1] <= s[i]; ++j)
      right = std::min(right, s[j + 1]);
    if (s[i] - std::max(left, right) < 0.3 * s[i]) continue;
    double count = 0.0, moment = 0.0;
    for (std::size_t j = i - 2; j <= i + 2; ++j) {
      count += p[j];
      moment += p[j] * static_cast<double>(j);
    }
    if (count < min_count) continue;
    peaks.push_back({o.elevation_of_bin(moment / count), o.profile_dz[i], count});
  }
  return peaks;
}

/// One beam being fitted: tau = t + dz u with u = 1/h, tau = z/h.
struct Beam {
  double t = 0.0, dz = 0.0;
  bool measured = true;
  std::size_t inliers = 0;
  double rms = 0.0;        ///< rad
  double threshold = 0.0;  ///< rad, residual band of its points
};

SensorConfig lookup_model(const std::vector<Beam>& beams) {
  SensorConfig s;
  s.preset = "custom";
  s.N_scan = static_cast<int>(beams.size());
  s.Horizon_SCAN = 360;
  for (const Beam& b : beams) {
    s.beam_elevations_deg.push_back(std::atan(b.t) / kDeg);
    s.beam_vertical_offsets_m.push_back(b.dz);
  }
  return s;
}

/// Sorts the beams and keeps one of two that are the same cone: elevations within 0.03 deg and
/// origin heights within 2 cm (no sensor has beams that close; the HDL-64E's closest pair, 0.085
/// deg apart, sits in different blocks). The one with more points stays.
void sort_unique(std::vector<Beam>& beams) {
  constexpr double kSameTan = 0.03 * kDeg, kSameOffset = 0.02;
  std::sort(beams.begin(), beams.end(), [](const Beam& a, const Beam& b) { return a.t < b.t; });
  std::vector<Beam> out;
  for (const Beam& b : beams) {
    if (!out.empty() && b.t - out.back().t < 2e-6) {  // BeamLookup needs increasing elevations
      if (b.inliers > out.back().inliers) out.back() = b;
      continue;
    }
    if (!out.empty() && b.t - out.back().t < kSameTan && std::abs(b.dz - out.back().dz) < kSameOffset) {
      if (b.inliers > out.back().inliers) out.back() = b;
      continue;
    }
    out.push_back(b);
  }
  beams = std::move(out);
}

/// Assignment of the points to beams and the residual of each (tau from its beam's origin).
struct Assignment {
  std::vector<int> row;      ///< -1: outside every beam's band
  std::vector<float> res;    ///< rad
  std::vector<char> inlier;  ///< within its beam's threshold
};

void assign(const std::vector<Sample>& pts, const std::vector<Beam>& beams, Assignment& a) {
  const SensorConfig model = lookup_model(beams);
  const BeamLookup lookup(model);
  a.row.assign(pts.size(), -1);
  a.res.assign(pts.size(), 0.0f);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pts.size(), 1 << 14), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Sample& s = pts[i];
      const int k0 = lookup.row(Vec3(s.h, 0.0, s.z));
      if (k0 < 0) continue;
      // The nearest cone among the neighbours of the row found: beams of laser blocks at different
      // heights can cross (interleaved HDL-64E blocks), where the row bands are ambiguous.
      const double u = 1.0 / s.h, tau = s.z / s.h;
      int best = k0;
      double best_res = INFINITY;
      const int lo = std::max(0, k0 - 4), hi = std::min(static_cast<int>(beams.size()) - 1, k0 + 4);
      for (int k = lo; k <= hi; ++k) {
        const Beam& b = beams[static_cast<std::size_t>(k)];
        const double r = tau - b.t - b.dz * u;
        if (std::abs(r) < std::abs(best_res)) {
          best_res = r;
          best = k;
        }
      }
      a.row[i] = best;
      a.res[i] = static_cast<float>(best_res);
    }
  });
}

/// Points per beam, by index.
std::vector<std::vector<std::uint32_t>> members(const Assignment& a, std::size_t beams) {
  std::vector<std::vector<std::uint32_t>> m(beams);
  for (std::size_t i = 0; i < a.row.size(); ++i)
    if (a.row[i] >= 0) m[static_cast<std::size_t>(a.row[i])].push_back(static_cast<std::uint32_t>(i));
  return m;
}

/// Assignment with the beams' current bands: which points lie on their beam.
void classify(const std::vector<Sample>& pts, const std::vector<Beam>& beams, Assignment& a) {
  assign(pts, beams, a);
  a.inlier.assign(pts.size(), 0);
  for (std::size_t i = 0; i < pts.size(); ++i)
    a.inlier[i] = a.row[i] >= 0 && std::abs(a.res[i]) <= beams[static_cast<std::size_t>(a.row[i])].threshold;
}

/// Robust fits of every beam to its points; beams with fewer than `min_points` are removed.
/// Returns the largest change of a beam's line (rad at u = 0.1, i.e. 10 m).
double fit_beams(const std::vector<Sample>& pts, std::vector<Beam>& beams, Assignment& a, double min_points,
                 double fallback_dz) {
  assign(pts, beams, a);
  const auto m = members(a, beams.size());
  a.inlier.assign(pts.size(), 0);
  std::vector<Beam> fitted = beams;
  std::vector<char> keep(beams.size(), 1);
  // Robust residual scale of every beam (1.4826 median absolute residual) and their median: one
  // beam much wider than the others holds the points of several and must not keep them.
  std::vector<double> sigma(beams.size(), 0.0);
  for (std::size_t k = 0; k < beams.size(); ++k) {
    const auto& idx = m[k];
    if (static_cast<double>(idx.size()) < min_points) continue;
    std::vector<float> absres(idx.size());
    for (std::size_t j = 0; j < idx.size(); ++j) absres[j] = std::abs(a.res[idx[j]]);
    auto mid = absres.begin() + static_cast<std::ptrdiff_t>(absres.size() / 2);
    std::nth_element(absres.begin(), mid, absres.end());
    sigma[k] = 1.4826 * static_cast<double>(*mid);
  }
  std::vector<double> sorted_sigma;
  for (std::size_t k = 0; k < beams.size(); ++k)
    if (static_cast<double>(m[k].size()) >= min_points) sorted_sigma.push_back(sigma[k]);
  double typical = kResidualFloor;
  if (!sorted_sigma.empty()) {
    std::nth_element(sorted_sigma.begin(),
                     sorted_sigma.begin() + static_cast<std::ptrdiff_t>(sorted_sigma.size() / 2),
                     sorted_sigma.end());
    typical = std::max(typical, sorted_sigma[sorted_sigma.size() / 2]);
  }
  for (std::size_t k = 0; k < beams.size(); ++k) {
    const auto& idx = m[k];
    Beam& b = fitted[k];
    if (static_cast<double>(idx.size()) < min_points) {
      keep[k] = 0;
      continue;
    }
    // Band: three robust standard deviations, at least the coordinate precision, at most 45 % of
    // the gap to the neighbouring beams and at most 10 typical standard deviations.
    double gap = INFINITY;
    if (k > 0) gap = std::min(gap, beams[k].t - beams[k - 1].t);
    if (k + 1 < beams.size()) gap = std::min(gap, beams[k + 1].t - beams[k].t);
    b.threshold = std::min({std::max(3.0 * sigma[k], kResidualFloor), 0.45 * gap, 10.0 * typical});
    double n = 0, su = 0, suu = 0, st = 0, sut = 0;
    for (const std::uint32_t i : idx) {
      if (std::abs(a.res[i]) > b.threshold) continue;
      a.inlier[i] = 1;
      const double u = 1.0 / pts[i].h, tau = pts[i].z / pts[i].h;
      n += 1.0;
      su += u;
      suu += u * u;
      st += tau;
      sut += u * tau;
    }
    if (n < min_points) {
      keep[k] = 0;
      continue;
    }
    const double var_u = suu - su * su / n;  // sum of squared deviations of u
    Eigen::Matrix2d A;
    A << n, su, su, suu;
    const Eigen::Vector2d sol = A.ldlt().solve(Eigen::Vector2d(st, sut));
    double sse = 0.0;
    for (const std::uint32_t i : idx) {
      if (std::abs(a.res[i]) > b.threshold) continue;
      const double e = pts[i].z / pts[i].h - sol(0) - sol(1) / pts[i].h;
      sse += e * e;
    }
    const double rms = std::sqrt(sse / n);
    const double sigma_dz = var_u > 0.0 ? std::max(rms, kResidualFloor / 3.0) / std::sqrt(var_u) : INFINITY;
    b.measured = sigma_dz < 0.003 && std::abs(sol(1)) < 1.0;
    if (b.measured) {
      b.t = sol(0);
      b.dz = sol(1);
    }
    b.inliers = static_cast<std::size_t>(n);
    b.rms = rms;
  }
  // Beams whose points all lie at about one distance (ground rings, a wall): the height of the
  // nearest measured beams (interpolated within a block, the nearer one across a block step), then
  // the elevation that fits its points from there.
  for (std::size_t k = 0; k < fitted.size(); ++k) {
    Beam& b = fitted[k];
    if (!keep[k] || b.measured) continue;
    long below = static_cast<long>(k) - 1, above = static_cast<long>(k) + 1;
    while (below >= 0 &&
           !(keep[static_cast<std::size_t>(below)] && fitted[static_cast<std::size_t>(below)].measured))
      --below;
    while (above < static_cast<long>(fitted.size()) &&
           !(keep[static_cast<std::size_t>(above)] && fitted[static_cast<std::size_t>(above)].measured))
      ++above;
    const bool has_below = below >= 0, has_above = above < static_cast<long>(fitted.size());
    double dz = fallback_dz;
    if (has_below && has_above) {
      const Beam& lo = fitted[static_cast<std::size_t>(below)];
      const Beam& hi = fitted[static_cast<std::size_t>(above)];
      if (std::abs(hi.dz - lo.dz) < 0.01) {
        const double f = (b.t - lo.t) / (hi.t - lo.t);
        dz = lo.dz + std::clamp(f, 0.0, 1.0) * (hi.dz - lo.dz);
      } else {
        dz = (b.t - lo.t < hi.t - b.t) ? lo.dz : hi.dz;
      }
    } else if (has_below) {
      dz = fitted[static_cast<std::size_t>(below)].dz;
    } else if (has_above) {
      dz = fitted[static_cast<std::size_t>(above)].dz;
    }
    double sum = 0.0, n = 0.0;
    for (const std::uint32_t i : m[k]) {
      if (std::abs(a.res[i]) > b.threshold) continue;
      sum += (pts[i].z - dz) / pts[i].h;
      n += 1.0;
    }
    b.dz = dz;
    if (n > 0.0) b.t = sum / n;
  }
  double change = 0.0;
  std::vector<Beam> out;
  for (std::size_t k = 0; k < fitted.size(); ++k) {
    if (!keep[k]) {
      change = INFINITY;
      continue;
    }
    change =
        std::max(change, std::abs(fitted[k].t - beams[k].t) + 0.1 * std::abs(fitted[k].dz - beams[k].dz));
    out.push_back(fitted[k]);
  }
  beams = std::move(out);
  sort_unique(beams);
  return change;
}

/// Beams of the points: detection on the origin-height histograms, then fits, then detection
/// again among the points no beam explains, up to three times.
std::vector<Beam> find_beams(const std::vector<Sample>& pts, double max_offset, Assignment& a) {
  auto detect = [&](const std::vector<std::uint32_t>* subset) {
    std::vector<Sample> hough;
    const std::size_t n = subset ? subset->size() : pts.size();
    const std::size_t stride = std::max<std::size_t>(1, (n + kHoughPoints - 1) / kHoughPoints);
    for (std::size_t j = 0; j < n; j += stride) hough.push_back(pts[subset ? (*subset)[j] : j]);
    const OffsetHistograms o = offset_histograms(hough, max_offset);
    const double min_count =
        std::max(10.0, 2e-4 * static_cast<double>(pts.size()) / static_cast<double>(stride));
    std::vector<Beam> beams;
    for (const Peak& p : find_peaks(o, min_count))
      beams.push_back({std::tan(p.elevation_deg * kDeg), p.offset_m});
    return std::make_pair(beams, o.global_dz);
  };
  auto [beams, global_dz] = detect(nullptr);
  sort_unique(beams);

  if (beams.size() < 2)
    fail("the point elevations show " + std::to_string(beams.size()) +
         " beam(s): no spinning multi-beam LiDAR (need at least 2 beams)");
  for (int round = 0;; ++round) {
    for (int iteration = 0; iteration < 10 && beams.size() >= 2; ++iteration) {
      // The size threshold follows the beams found: 1 % of the median beam.
      std::vector<std::size_t> sizes;
      for (const Beam& b : beams) sizes.push_back(b.inliers);
      std::nth_element(sizes.begin(), sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2),
                       sizes.end());
      const double min_points = std::max(30.0, 0.01 * static_cast<double>(sizes[sizes.size() / 2]));
      const double change = fit_beams(pts, beams, a, min_points, global_dz);
      if (change < 1e-5) break;  // rad: below the 0.001 deg of the written table
    }
    if (beams.size() < 2 || round == 3) break;
    classify(pts, beams, a);
    std::vector<std::uint32_t> unexplained;
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (!a.inlier[i]) unexplained.push_back(static_cast<std::uint32_t>(i));
    if (static_cast<double>(unexplained.size()) < std::max(200.0, 0.005 * static_cast<double>(pts.size())))
      break;
    auto [more, unused] = detect(&unexplained);
    (void)unused;
    // A new beam must not be an existing one: its line at 10 m must lie outside their bands (and
    // sort_unique() keeps the fitted one of two nearly equal cones).
    const std::size_t before = beams.size();
    for (const Beam& c : more) {
      bool known = false;
      for (const Beam& b : beams)
        known =
            known || std::abs((c.t + 0.1 * c.dz) - (b.t + 0.1 * b.dz)) < std::max(2.0 * b.threshold, 1e-4);
      if (!known) beams.push_back(c);
    }
    sort_unique(beams);
    if (beams.size() == before) break;
  }
  if (beams.size() < 2)
    fail("found " + std::to_string(beams.size()) + " beam(s) with enough points (need at least 2)");
  classify(pts, beams, a);
  return beams;
}

/// Horizon_SCAN for `firings` per turn: the largest of the usual image widths that does not
/// exceed it by more than 3 %, so that each column holds at most one firing of a beam.
int image_width(double firings) {
  static const int kWidths[] = {256,  360,  400,  450,   480,   500,   512,   600,  720,  750,  800,
                                900,  1000, 1024, 1080,  1200,  1440,  1500,  1600, 1800, 2000, 2048,
                                2160, 2400, 2880, 3000,  3600,  4000,  4096,  4500, 5000, 6000, 7200,
                                8000, 8192, 9000, 10000, 12000, 14400, 16000, 16384};
  int best = 0;
  for (const int w : kWidths)
    if (w <= 1.03 * firings) best = w;
  if (best == 0) best = std::max(16, static_cast<int>(std::round(firings / 8.0)) * 8);
  return best;
}

/// Azimuth step between neighbouring points of one beam in one scan: the mode of the gaps, over
/// the points of up to three scans at full resolution, each given the row of its beam.
double azimuth_step_deg(const std::vector<std::vector<Vec3>>& scans, const std::vector<Beam>& beams,
                        double vertical_correction_deg) {
  const SensorConfig model = lookup_model(beams);
  const BeamLookup lookup(model);
  constexpr double kLo = 0.02, kHi = 4.0, kBin = 0.001;
  std::vector<double> gaps;
  std::vector<double> hist(static_cast<std::size_t>((kHi - kLo) / kBin) + 1, 0.0);
  for (std::size_t s = 0; s < std::min<std::size_t>(3, scans.size()); ++s) {
    std::vector<Vec3> points = scans[s];
    correct_vertical_angle(points, vertical_correction_deg);
    std::vector<std::pair<int, float>> row_azimuth;
    for (const Vec3& p : points) {
      if (!p.allFinite()) continue;
      const int k = lookup.row(p);
      if (k < 0) continue;
      const Beam& b = beams[static_cast<std::size_t>(k)];
      const double h = std::hypot(p.x(), p.y());
      if (std::abs((p.z() - b.dz) / h - b.t) > b.threshold) continue;
      row_azimuth.emplace_back(k, static_cast<float>(std::atan2(p.y(), p.x()) / kDeg));
    }
    std::sort(row_azimuth.begin(), row_azimuth.end());
    for (std::size_t j = 1; j < row_azimuth.size(); ++j) {
      if (row_azimuth[j].first != row_azimuth[j - 1].first) continue;
      const double g = row_azimuth[j].second - row_azimuth[j - 1].second;
      if (g < kLo || g >= kHi) continue;
      gaps.push_back(g);
      hist[static_cast<std::size_t>((g - kLo) / kBin)] += 1.0;
    }
  }
  if (gaps.size() < 100) return 0.0;
  // Mode of the histogram smoothed over +-0.005 deg, then the median of the gaps near it.
  double best = -1.0, mode = 0.0;
  for (std::size_t i = 0; i < hist.size(); ++i) {
    double sum = 0.0;
    for (std::size_t j = i >= 5 ? i - 5 : 0; j <= std::min(hist.size() - 1, i + 5); ++j) sum += hist[j];
    if (sum > best) {
      best = sum;
      mode = kLo + (static_cast<double>(i) + 0.5) * kBin;
    }
  }
  std::vector<double> near;
  for (const double g : gaps)
    if (g > 0.8 * mode && g < 1.25 * mode) near.push_back(g);
  auto mid = near.begin() + static_cast<std::ptrdiff_t>(near.size() / 2);
  std::nth_element(near.begin(), mid, near.end());
  return *mid;
}

double quantile(std::vector<float> v, double q) {
  auto at = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

double median_spacing(const SensorConfig& s) {
  std::vector<double> d;
  for (int k = 1; k < s.N_scan; ++k) d.push_back(s.beam_elevation_deg(k) - s.beam_elevation_deg(k - 1));
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

double table_distance(const SensorConfig& a, const SensorConfig& b) {
  auto one_way = [](const SensorConfig& x, const SensorConfig& y) {
    double sum = 0.0;
    for (int i = 0; i < x.N_scan; ++i) {
      double best = INFINITY;
      for (int j = 0; j < y.N_scan; ++j)
        best = std::min(best, std::abs(x.beam_elevation_deg(i) - y.beam_elevation_deg(j)));
      sum += best;
    }
    return sum / x.N_scan;
  };
  return 0.5 * (one_way(a, b) + one_way(b, a));
}
}  // namespace

SensorModelEstimate estimate_sensor_model(const std::vector<std::vector<Vec3>>& scans,
                                          const std::vector<double>& stamps,
                                          const SensorEstimationConfig& config) {
  SensorModelEstimate est;
  est.scans = scans.size();
  std::size_t usable = 0;
  for (const auto& scan : scans) est.points += scan.size();
  for (const auto& scan : scans)
    for (const Vec3& p : scan) usable += p.allFinite() && std::hypot(p.x(), p.y()) >= config.min_horizontal_m;
  const std::size_t stride = std::max<std::size_t>(1, (usable + config.max_points - 1) / config.max_points);

  // The points as the fit sees them (vertical correction applied), and their ranges.
  std::vector<Sample> pts;
  std::vector<float> ranges;
  pts.reserve(usable / stride + 1);
  std::size_t counter = 0, range_counter = 0;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    std::vector<Vec3> points = scans[s];
    correct_vertical_angle(points, config.vertical_angle_correction_deg);
    for (const Vec3& p : points) {
      if (!p.allFinite()) continue;
      const double r = p.norm();
      if (r > 1e-3 && range_counter++ % stride == 0) ranges.push_back(static_cast<float>(r));
      const double h = std::hypot(p.x(), p.y());
      if (h < config.min_horizontal_m) continue;
      if (counter++ % stride != 0) continue;
      pts.push_back(
          {static_cast<float>(h), static_cast<float>(p.z()), static_cast<float>(std::atan2(p.y(), p.x()))});
    }
  }
  est.points_used = pts.size();
  const std::string where = std::to_string(est.points) + " points in " + std::to_string(scans.size()) +
                            (scans.size() == 1 ? " scan" : " scans");
  if (pts.size() < kMinPoints)
    fail("only " + std::to_string(pts.size()) + " of the " + where + " lie " +
         fixed(config.min_horizontal_m, 1) +
         " m or more from the rotation axis; the estimate needs at least " + std::to_string(kMinPoints));

  // All points in one plane: no distance spread, so beam elevations and origin heights cannot be
  // told apart (and a planar cloud is no LiDAR sweep of a street).
  {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    const std::size_t step = std::max<std::size_t>(1, pts.size() / 200000);
    double n = 0.0;
    for (std::size_t i = 0; i < pts.size(); i += step) {
      const Sample& s = pts[i];
      const Eigen::Vector3d p(s.h * std::cos(s.azimuth), s.h * std::sin(s.azimuth), s.z);
      mean += p;
      second += p * p.transpose();
      n += 1.0;
    }
    mean /= n;
    const Eigen::Matrix3d cov = second / n - mean * mean.transpose();
    const double thickness =
        std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues()(0)));
    if (thickness < 0.02)
      fail("all " + where + " lie within " + fixed(100.0 * thickness, 1) +
           " cm (rms) of one plane: the beams cannot be told apart from their distances; use scans of a "
           "scene with depth (streets, buildings)");
  }

  Assignment a;
  std::vector<Beam> beams = find_beams(pts, config.max_offset_m, a);

  // Beams of a LiDAR are sharp: their points scatter far less than the beams are apart. Points
  // spread evenly over the elevations (no beams, or a cloud not in the sensor frame) give "beams"
  // that fill the space between them.
  std::vector<double> rms, gaps;
  for (std::size_t k = 0; k < beams.size(); ++k) {
    rms.push_back(beams[k].rms);
    if (k > 0) gaps.push_back(beams[k].t - beams[k - 1].t);
  }
  std::nth_element(rms.begin(), rms.begin() + static_cast<std::ptrdiff_t>(rms.size() / 2), rms.end());
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
  const double spread = rms[rms.size() / 2] / gaps[gaps.size() / 2];
  if (spread > kMaxSpread)
    fail("the point elevations form no distinct beams (the " + std::to_string(beams.size()) +
         " candidates scatter by " + fixed(100.0 * spread, 0) +
         " % of their spacing): not the points of a spinning LiDAR in its sensor frame (tilted, moved or "
         "merged "
         "clouds blur the beams)");

  std::size_t on_beam = 0;
  for (const char c : a.inlier) on_beam += c != 0;
  est.on_beam_fraction = static_cast<double>(on_beam) / static_cast<double>(pts.size());
  if (est.on_beam_fraction < kMinOnBeam)
    fail("only " + fixed(100.0 * est.on_beam_fraction, 1) + " % of the " + where + " lie on the " +
         std::to_string(beams.size()) +
         " beams found: are the points in the sensor frame (not tilted, moved or merged from several "
         "sensors)?");

  SensorConfig& s = est.sensor;
  s.preset = "custom";
  s.vertical_angle_correction_deg = config.vertical_angle_correction_deg;
  std::size_t guessed = 0;
  for (const Beam& b : beams) {
    const double e = std::round(std::atan(b.t) / kDeg * 1000.0) / 1000.0;
    if (!s.beam_elevations_deg.empty() && e <= s.beam_elevations_deg.back()) continue;  // same at 0.001 deg
    s.beam_elevations_deg.push_back(e);
    s.beam_vertical_offsets_m.push_back(std::round(b.dz * 1000.0) / 1000.0);
    est.beams.push_back({e, b.dz, b.measured, std::atan(b.rms) / kDeg, b.inliers});
    guessed += !b.measured;
  }
  s.N_scan = static_cast<int>(s.beam_elevations_deg.size());
  s.Pit_bottom = s.beam_elevations_deg.front();
  s.fov_top = s.beam_elevations_deg.back();
  if (std::all_of(s.beam_vertical_offsets_m.begin(), s.beam_vertical_offsets_m.end(),
                  [](double dz) { return dz == 0.0; }))
    s.beam_vertical_offsets_m.clear();
  if (guessed > 0)
    est.notes.push_back(std::to_string(guessed) +
                        " beam(s) saw everything at about one distance: their origin heights are those of "
                        "their neighbours");

  est.azimuth_step_deg = azimuth_step_deg(scans, beams, config.vertical_angle_correction_deg);
  if (est.azimuth_step_deg > 0.0) {
    s.Horizon_SCAN = image_width(360.0 / est.azimuth_step_deg);
  } else {
    s.Horizon_SCAN = 1800;
    est.notes.push_back("too few neighbouring points on the beams to measure the azimuth step: 1800 columns");
  }

  // Range limits: the nearest 0.1 % and the farthest 0.01 % of the returns, with margins.
  s.min_range = std::floor(0.9 * quantile(ranges, 0.001) * 10.0) / 10.0;
  s.max_range = std::max(std::ceil(1.05 * quantile(ranges, 0.9999)), s.min_range + 1.0);

  std::vector<double> periods;
  for (std::size_t i = 1; i < stamps.size(); ++i)
    if (stamps[i] > stamps[i - 1]) periods.push_back(stamps[i] - stamps[i - 1]);
  if (!periods.empty()) {
    std::nth_element(periods.begin(), periods.begin() + static_cast<std::ptrdiff_t>(periods.size() / 2),
                     periods.end());
    const double rate = 1.0 / periods[periods.size() / 2];
    if (rate >= 1.0 && rate <= 100.0) {
      s.scan_rate_hz = std::round(rate * 100.0) / 100.0;
      est.scan_rate_measured = true;
    }
  }
  if (!est.scan_rate_measured) {
    s.scan_rate_hz = 10.0;
    est.notes.push_back("no usable scan times: scan rate 10 Hz assumed");
  }
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    fail(std::string("the estimated model is not valid: ") + e.what());
  }
  return est;
}

PresetMatch match_preset(const SensorConfig& sensor, const std::string& preset) {
  const SensorConfig p = sensor_preset(preset);
  PresetMatch m;
  m.preset = p.preset;
  m.preset_beams = p.N_scan;
  m.distance_deg = table_distance(sensor, p);
  m.resembles = p.N_scan == sensor.N_scan && m.distance_deg < 0.25 * median_spacing(p);
  return m;
}

PresetMatch nearest_preset(const SensorConfig& sensor) {
  PresetMatch best;
  best.distance_deg = INFINITY;
  for (const std::string& name : sensor_preset_names()) {
    const PresetMatch m = match_preset(sensor, name);
    if (m.distance_deg < best.distance_deg) best = m;
  }
  return best;
}

}  // namespace dloam
