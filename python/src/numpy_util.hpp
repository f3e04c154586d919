// numpy arrays over dloam's vectors. A vector moved in is owned by the array (a capsule frees it):
// labels, poses and map points reach Python without a copy. Points are converted once into the
// N x 4 float32 layout (x, y, z, intensity) of KITTI .bin scans.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::python {

namespace py = pybind11;

/// Hands `v` over to a numpy array of `shape` / byte `strides` over its elements' storage.
template <class Element, class Scalar>
py::array_t<Scalar> adopt(std::vector<Element>&& v, std::vector<py::ssize_t> shape,
                          std::vector<py::ssize_t> strides) {
  auto* owned = new std::vector<Element>(std::move(v));
  py::capsule free(owned, [](void* p) { delete static_cast<std::vector<Element>*>(p); });
  return py::array_t<Scalar>(std::move(shape), std::move(strides),
                             reinterpret_cast<const Scalar*>(owned->data()), free);
}

/// 1-D array owning `v`.
template <class T>
py::array_t<T> to_numpy(std::vector<T>&& v) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return adopt<T, T>(std::move(v), {n}, {static_cast<py::ssize_t>(sizeof(T))});
}

/// K x 4 x 4 float64 (row-major view of Eigen's column-major 4 x 4 matrices, no copy).
py::array_t<double> poses_to_numpy(std::vector<Pose>&& poses);
/// 4 x 4 float64 copy.
py::array_t<double> pose_to_numpy(const Pose& pose);
/// N x 3 float64 owning `points` (no copy).
py::array_t<double> points_to_numpy(std::vector<Vec3>&& points);

/// A 4 x 4 matrix (any numeric dtype) as a pose; throws std::invalid_argument otherwise.
Pose pose_from_numpy(const py::handle& matrix);
/// K x 4 x 4 as poses.
std::vector<Pose> poses_from_numpy(const py::handle& matrices);

/// N x 4 float32: x, y, z, intensity (0 without intensity).
py::array_t<float> cloud_points(const PointCloud& cloud);
/// The per-point times (N float32, fractions of the sweep) or None.
py::object cloud_times(const PointCloud& cloud);

/// A scan from N x 3 or N x 4 points (x y z [intensity]), optional N times and stamp.
PointCloud cloud_from_numpy(const py::handle& points, const py::handle& times, std::optional<double> stamp);

}  // namespace dloam::python
