// Thinning a sequence: keeping every N-th scan and/or dropping scans at random, with the kept
// scans' true times, poses and labels, to test a pipeline at a lower scan rate or with lost scans.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dloam::io {

struct ThinOptions {
  int keep_every = 1;      ///< keep scans 0, N, 2N, ...
  double drop = 0.0;       ///< then drop each of those with this probability, in [0, 1)
  std::uint64_t seed = 1;  ///< of the drop draws
  /// Throws std::invalid_argument naming the bad value.
  void validate() const;
};

/// Indices of the scans kept of `n`: scan i is kept when i % keep_every == 0 and the i-th
/// uniform draw in [0, 1) of std::mt19937_64(seed) (one draw per scan, kept or not) is not below
/// `drop`. The same options give the same scans for `dloam simulate` and `dloam thin`. Throws
/// std::invalid_argument when no scan is kept.
std::vector<std::size_t> select_scans(std::size_t n, const ThinOptions& options);

struct ThinResult {
  std::size_t input_scans = 0;
  std::vector<std::size_t> kept;  ///< input scan indices, in order
  bool hard_links = true;         ///< false: some scan or label files were copied
};

/// Writes the kept scans of the sequence folder `in` (KITTI .bin or PCD layout) to `out` in the
/// same layout, renumbered from 000000 (hard links to the input files where the file system
/// allows, copies otherwise), with their labels, poses.txt (the kept lines; relative to the
/// first kept scan when scan 0 is dropped), times.txt (the kept lines, or i / scan_rate_hz when
/// `in` has none), calib.txt (copied) and kept_scans.txt (the input index of each output scan).
/// Throws InputError when `out` is `in` or lies inside it, when `out` already holds scans and
/// `overwrite` is false, or on bad input.
ThinResult thin_sequence(const std::string& in, const std::string& out, const ThinOptions& options,
                         double scan_rate_hz, bool overwrite);

}  // namespace dloam::io
