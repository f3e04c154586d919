// timing.csv of a run: milliseconds per scan and pipeline module, plus the per-scan feature counts
// and flags. Written by `dloam run` and `dloam_node`.
#pragma once

#include <string>
#include <vector>

#include "dloam/pipeline/pipeline.hpp"

namespace dloam::io {

/// Columns: scan, <module>_ms..., edges, planes, mapped, keyframe, loop_closed, degenerate, the
/// step check and search flags, and the degeneracy of the odometry and of the scan-to-map job
/// integrated at the scan (smallest eigenvalue, its axis, unconstrained directions).
/// Written atomically.
void write_timing_csv(const std::string& path, const std::vector<ScanResult>& results);

}  // namespace dloam::io
