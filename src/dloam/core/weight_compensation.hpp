// Weight compensation of features near dynamic objects (paper eq. 15): the background next to a
// dynamic object has occlusion holes, so a feature at a yaw difference theta from the nearest
// dynamic pixel gets s_comp = s * (1 - R_horiz / |theta|) (0 when |theta| <= R_horiz). With theta
// measured in range-image columns (|theta| / R_horiz = d columns) the factor is 1 - 1/d.
#pragma once

#include <cstdint>
#include <vector>

#include "dloam/core/range_image.hpp"

namespace dloam {

/// Per column: circular distance (columns) to the nearest column holding a dynamic pixel;
/// -1 everywhere when there is none. `pixel_dynamic` is rows*cols (may be empty: no dynamic).
std::vector<int> dynamic_column_distance(const std::vector<std::uint8_t>& pixel_dynamic, int rows, int cols);

/// 1 - 1/d clamped to [0, 1]; d < 0 (no dynamic object) gives 1.
double compensation_factor(int column_distance);

/// Weights of features (input point indices) of an image: base weight 1 times eq. 15's factor.
std::vector<double> compensated_weights(const std::vector<int>& feature_points, const RangeImage& image,
                                        const std::vector<int>& column_distance);

}  // namespace dloam
