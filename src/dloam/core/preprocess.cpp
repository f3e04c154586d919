#include "dloam/core/preprocess.hpp"

#include <cmath>

namespace dloam {

void correct_vertical_angle(std::vector<Vec3>& points, double degrees) {
  if (degrees == 0.0) return;
  const double d = degrees * M_PI / 180.0;
  const double c = std::cos(d), s = std::sin(d);
  for (Vec3& p : points) {
    const double h = std::hypot(p.x(), p.y());
    if (h < 1e-9) continue;
    // Rotate (h, z) by d in the vertical plane of the point's azimuth.
    const double h2 = c * h - s * p.z();
    const double z2 = s * h + c * p.z();
    p.x() *= h2 / h;
    p.y() *= h2 / h;
    p.z() = z2;
  }
}

}  // namespace dloam
