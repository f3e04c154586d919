#include "numpy_util.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dloam::python {

static_assert(sizeof(Pose) == 16 * sizeof(double), "Pose is a packed 4 x 4 column-major matrix");
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");

py::array_t<double> poses_to_numpy(std::vector<Pose>&& poses) {
  const auto k = static_cast<py::ssize_t>(poses.size());
  constexpr py::ssize_t d = sizeof(double);
  return adopt<Pose, double>(std::move(poses), {k, 4, 4}, {16 * d, d, 4 * d});
}

py::array_t<double> pose_to_numpy(const Pose& pose) {
  py::array_t<double> out({4, 4});
  auto m = out.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = pose.matrix()(r, c);
  return out;
}

py::array_t<double> points_to_numpy(std::vector<Vec3>&& points) {
  const auto n = static_cast<py::ssize_t>(points.size());
  constexpr py::ssize_t d = sizeof(double);
  return adopt<Vec3, double>(std::move(points), {n, 3}, {3 * d, d});
}

Pose pose_from_numpy(const py::handle& matrix) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(matrix);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    throw std::invalid_argument("expected a 4 x 4 matrix");
  Pose pose;
  const auto m = a.unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = m(r, c);
  return pose;
}

std::vector<Pose> poses_from_numpy(const py::handle& matrices) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(matrices);
  if (!a || a.ndim() != 3 || a.shape(1) != 4 || a.shape(2) != 4)
    throw std::invalid_argument("expected poses as a K x 4 x 4 array");
  std::vector<Pose> out(static_cast<std::size_t>(a.shape(0)));
  const auto m = a.unchecked<3>();
  for (py::ssize_t k = 0; k < a.shape(0); ++k)
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) out[static_cast<std::size_t>(k)].matrix()(r, c) = m(k, r, c);
  return out;
}

py::array_t<float> cloud_points(const PointCloud& cloud) {
  const auto n = static_cast<py::ssize_t>(cloud.size());
  py::array_t<float> out({n, py::ssize_t{4}});
  float* p = out.mutable_data();
  const bool intensity = cloud.has_intensity();
  for (std::size_t i = 0; i < cloud.size(); ++i, p += 4) {
    p[0] = static_cast<float>(cloud.xyz[i].x());
    p[1] = static_cast<float>(cloud.xyz[i].y());
    p[2] = static_cast<float>(cloud.xyz[i].z());
    p[3] = intensity ? cloud.intensity[i] : 0.0f;
  }
  return out;
}

py::object cloud_times(const PointCloud& cloud) {
  if (!cloud.has_time()) return py::none();
  std::vector<float> t = cloud.time;
  return to_numpy(std::move(t));
}

PointCloud cloud_from_numpy(const py::handle& points, const py::handle& times, std::optional<double> stamp) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(points);
  if (!a || a.ndim() != 2 || (a.shape(1) != 3 && a.shape(1) != 4))
    throw std::invalid_argument("points: expected an N x 3 or N x 4 array (x, y, z[, intensity])");
  const std::size_t n = static_cast<std::size_t>(a.shape(0));
  const bool intensity = a.shape(1) == 4;
  PointCloud cloud;
  cloud.xyz.resize(n);
  if (intensity) cloud.intensity.resize(n);
  const auto m = a.unchecked<2>();
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<py::ssize_t>(i);
    cloud.xyz[i] = Vec3(m(k, 0), m(k, 1), m(k, 2));
    if (!cloud.xyz[i].allFinite())
      throw InputError("points: point " + std::to_string(i) + " has a NaN or infinite coordinate");
    if (intensity) cloud.intensity[i] = static_cast<float>(m(k, 3));
  }
  if (!times.is_none()) {
    const auto t = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(times);
    if (!t || t.ndim() != 1 || static_cast<std::size_t>(t.shape(0)) != n)
      throw std::invalid_argument("times: expected one time per point (fractions of the sweep in [0, 1))");
    cloud.time.assign(t.data(), t.data() + n);
  }
  cloud.stamp = stamp;
  return cloud;
}

}  // namespace dloam::python
