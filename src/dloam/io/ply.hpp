// PLY point clouds (the global map is written as PLY): format ascii 1.0 or
// binary_little_endian 1.0; element vertex with x y z, optional intensity, optional
// uchar red green blue, optional float label. Other vertex properties are skipped on reading.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/io/encoding.hpp"

namespace dloam::io {

using Rgb = std::array<std::uint8_t, 3>;

struct PlyCloud {
  PointCloud cloud;          ///< xyz, and intensity when the file has it
  std::vector<Rgb> rgb;      ///< empty when the file has no red green blue
  std::vector<float> label;  ///< empty when the file has no label
};

/// Writes `cloud` (intensity when present) plus optional colours and labels (each empty or one
/// per point; otherwise throws InputError). Atomic.
void write_ply(const std::string& path, const PointCloud& cloud, Encoding encoding = Encoding::kBinary,
               const std::vector<Rgb>& rgb = {}, const std::vector<float>& label = {});

/// Reads the vertex element (it must be the file's first element). Rejects: missing file, bad
/// header, big-endian data, list properties in vertex, truncated data, NaN/Inf coordinates.
/// The vertex count is checked against the data size before anything is allocated.
PlyCloud read_ply(const std::string& path);
/// The same from the file's bytes; `name` is used in errors.
PlyCloud parse_ply(const std::string& bytes, const std::string& name);

}  // namespace dloam::io
