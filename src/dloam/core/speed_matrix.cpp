#include "dloam/core/speed_matrix.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace dloam {

namespace {

/// Distance of r to the range interval of the valid pixels among (rows r0,r1) x (cols c0,c1).
float bracket_distance(const std::vector<float>& prev, int cols, int r0, int r1, int c0, int c1, float r,
                       bool& behind) {
  float lo = 0.0f, hi = -1.0f;
  for (int v : {r0, r1})
    for (int u : {c0, c1}) {
      const float rp = prev[static_cast<std::size_t>(v * cols + u)];
      if (rp <= 0.0f) continue;
      if (hi < 0.0f) {
        lo = hi = rp;
      } else {
        lo = std::min(lo, rp);
        hi = std::max(hi, rp);
      }
    }
  behind = hi >= 0.0f && r > hi;
  if (hi < 0.0f) return -1.0f;
  return r < lo ? lo - r : (r > hi ? r - hi : 0.0f);
}

/// Eqs. 4-5 for the points seen from the previous frame: the row and its bracketing neighbour from
/// the sensor's BeamLookup (the same rows as the range image, beam origins included), the column
/// from the azimuth and its bracketing neighbour (pixel centres at col + 0.5).
class Projector {
 public:
  explicit Projector(const SensorConfig& s) : cols_(s.Horizon_SCAN), beams_(s) {}
  /// False when q is outside the vertical field of view (or at the origin).
  bool locate(const Vec3& q, int& row, int& row2, int& col, int& col2) const {
    if (!beams_.locate(q, row, row2)) return false;
    const double t = azimuth_time(q.x(), q.y()) * cols_;
    col = std::min(static_cast<int>(t), cols_ - 1);
    col2 = t - col >= 0.5 ? col + 1 : col - 1;  // wrapped without a division (every point of a scan)
    if (col2 == cols_) col2 = 0;
    if (col2 < 0) col2 = cols_ - 1;
    return true;
  }

 private:
  int cols_;
  BeamLookup beams_;
};

/// Speed (bracket distance) of the current point seen from the previous frame at q, and the
/// previous pixel it lands in (-1: outside the field of view or at the origin, speed -1).
float point_speed(const Vec3& q, const std::vector<float>& previous, const Projector& proj, int cols,
                  int& pixel, bool& behind) {
  pixel = -1;
  behind = false;
  const double r = q.norm();
  int row = 0, row2 = 0, col = 0, col2 = 0;
  if (!(r > 0.0) || !proj.locate(q, row, row2, col, col2)) return -1.0f;
  pixel = row * cols + col;
  return bracket_distance(previous, cols, row, row2, col, col2, static_cast<float>(r), behind);
}

void check_sizes(const RangeImage& current, const std::vector<float>& previous, const SensorConfig& sensor,
                 const char* what) {
  const auto n_pix = static_cast<std::size_t>(sensor.N_scan) * static_cast<std::size_t>(sensor.Horizon_SCAN);
  if (current.range.size() != n_pix || previous.size() != n_pix)
    throw InputError(std::string(what) + ": range images of " + std::to_string(current.range.size()) + " / " +
                     std::to_string(previous.size()) + " pixels, the sensor has " + std::to_string(n_pix));
}

}  // namespace

SpeedMatrix compute_speed_matrix(const RangeImage& current, const std::vector<Vec3>& current_points,
                                 const Pose& current_to_previous, const std::vector<float>& previous,
                                 const SensorConfig& sensor) {
  check_sizes(current, previous, sensor, "compute_speed_matrix");
  const int rows = sensor.N_scan, cols = sensor.Horizon_SCAN;
  SpeedMatrix S;
  S.rows = rows;
  S.cols = cols;
  S.speed.assign(current.range.size(), -1.0f);
  S.previous_pixel.assign(current.range.size(), -1);
  S.behind.assign(current.range.size(), 0);
  const Projector proj(sensor);
  // In point order (the points' memory is read sequentially), each point of a pixel once.
  const auto n = static_cast<int>(current_points.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096), [&](const tbb::blocked_range<int>& range) {
    for (int i = range.begin(); i < range.end(); ++i) {
      const int px = current.pixel_of_point(static_cast<std::size_t>(i));
      if (px < 0 || current.point_of_pixel[static_cast<std::size_t>(px)] != i) continue;
      const Vec3 q = current_to_previous * current_points[static_cast<std::size_t>(i)];
      bool behind = false;
      S.speed[static_cast<std::size_t>(px)] =
          point_speed(q, previous, proj, cols, S.previous_pixel[static_cast<std::size_t>(px)], behind);
      S.behind[static_cast<std::size_t>(px)] = behind ? 1 : 0;
    }
  });
  return S;
}

namespace {
// A surface seen at grazing incidence (terrain, a road beyond the ground segmentation): its range
// changes by metres from one row to the next, so any change of pose moves its points across rows to
// ranges that say nothing of motion, while standing still repeats the rows exactly. It votes for no
// motion whatever the motion is. Grazing: the segment to the pixel above or below lies within 20 deg
// of the ray.
bool grazing(const RangeImage& image, const std::vector<Vec3>& points, std::size_t px) {
  constexpr double kGrazingCos = 0.9397;  // cos(20 deg)
  const auto cols = static_cast<std::size_t>(image.cols);
  const int i = image.point_of_pixel[px];
  const Vec3& p = points[static_cast<std::size_t>(i)];
  for (const std::size_t other : {px + cols, px - cols}) {  // the row below / above (px - cols wraps)
    if (other >= image.point_of_pixel.size() || image.point_of_pixel[other] < 0) continue;
    const Vec3 d = points[static_cast<std::size_t>(image.point_of_pixel[other])] - p;
    if (std::abs(d.dot(p)) > kGrazingCos * d.norm() * p.norm()) return true;
  }
  return false;
}
}  // namespace

std::vector<int> static_area_pixels(const RangeImage& current, const std::vector<Vec3>& current_points,
                                    const std::vector<int>& pixel_label, int stride) {
  std::vector<int> out;
  const auto step = static_cast<std::size_t>(std::max(1, stride));
  for (std::size_t px = 0; px < pixel_label.size(); px += step) {
    const int i = current.point_of_pixel[px];
    if (i < 0 || pixel_label[px] <= 0 || grazing(current, current_points, px)) continue;
    out.push_back(static_cast<int>(px));
  }
  return out;
}

double static_area(const RangeImage& current, const std::vector<Vec3>& current_points,
                   const std::vector<int>& pixels, const Pose& current_to_previous,
                   const std::vector<float>& previous, const SensorConfig& sensor, double v_static) {
  return static_fit(current, current_points, pixels, current_to_previous, previous, sensor, v_static)
      .consistent;
}

StaticFit static_fit(const RangeImage& current, const std::vector<Vec3>& current_points,
                     const std::vector<int>& pixels, const Pose& current_to_previous,
                     const std::vector<float>& previous, const SensorConfig& sensor, double tolerance) {
  check_sizes(current, previous, sensor, "static_area");
  StaticFit fit;
  int pixel = -1;
  bool behind = false;
  const Projector proj(sensor);
  for (const int px : pixels) {
    const int i = current.point_of_pixel[static_cast<std::size_t>(px)];
    const Vec3 q = current_to_previous * current_points[static_cast<std::size_t>(i)];
    const float s = point_speed(q, previous, proj, sensor.Horizon_SCAN, pixel, behind);
    if (s < 0.0f) continue;
    fit.compared += q.squaredNorm();
    if (s < tolerance) fit.consistent += q.squaredNorm();
  }
  return fit;
}

}  // namespace dloam
