// PCD (Point Cloud Library) files, VERSION 0.7, DATA ascii or binary (binary_compressed is
// rejected as unsupported). Fields read: x y z, optional intensity, optional per-point time
// ("t" or "time"); any other fields are skipped. Any numeric TYPE/SIZE is accepted.
#pragma once

#include <string>
#include <vector>

#include "dloam/core/types.hpp"
#include "dloam/io/encoding.hpp"
#include "dloam/io/kitti.hpp"

namespace dloam::io {

/// Reads a PCD scan. Points with a NaN/Inf coordinate are no returns (organised clouds keep
/// their pixels so): they are dropped, and `info` (optional) receives the file's point count and
/// the file index of every point kept. Rejects: missing file, bad header, data shorter than the
/// header announces (checked before anything is allocated), empty cloud or no finite point, a
/// coordinate beyond 1e6 m, a NaN/Inf time or intensity (message names the file and the point).
/// Per-point times are kept when they already look like sweep fractions (all in [0, 1) and
/// spanning at least half of it); otherwise (seconds, nanoseconds, ...) they are rescaled
/// linearly to [0, 1) from their minimum and maximum.
PointCloud read_pcd(const std::string& path, ScanInfo* info = nullptr);
/// The same from the file's bytes; `name` is used in errors.
PointCloud parse_pcd(const std::string& bytes, const std::string& name, ScanInfo* info = nullptr);

/// Per-point times (any unit) as sweep fractions in [0, 1): kept when they already look like
/// fractions, else rescaled linearly from [min, max]. Shared by the PCD and rosbag readers.
std::vector<float> to_sweep_fraction(const std::vector<double>& t);

/// Writes float32 x y z, intensity (when present) and time (when present, as field `time_field`),
/// atomically.
void write_pcd(const std::string& path, const PointCloud& cloud, Encoding encoding = Encoding::kBinary,
               const std::string& time_field = "time");

}  // namespace dloam::io
