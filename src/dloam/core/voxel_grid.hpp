// Voxel-grid downsampling that keeps real input points: one representative per occupied voxel
// (the point nearest the voxel's centre), so callers keep each point's index.
#pragma once

#include <vector>

#include "dloam/core/types.hpp"

namespace dloam {

/// Indices into `points` (or into `subset` when given: then only those points are considered
/// and the returned values are elements of `subset`) of one point per voxel of size `leaf`,
/// in the order voxels are first met. `leaf <= 0` keeps every point. Deterministic.
/// Throws InputError on a non-finite point or one more than 2e9 voxels from the origin.
std::vector<int> voxel_downsample(const std::vector<Vec3>& points, double leaf,
                                  const std::vector<int>* subset = nullptr);

/// The points themselves, downsampled as above.
std::vector<Vec3> voxel_downsample_points(const std::vector<Vec3>& points, double leaf);

}  // namespace dloam
