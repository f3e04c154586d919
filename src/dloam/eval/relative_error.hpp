// KITTI odometry relative error, exactly as the devkit's evaluate_odometry.cpp computes it:
// path distances along the ground truth, segments of fixed length starting every `step` frames,
// per segment E = (P_f^-1 P_l)^-1 (G_f^-1 G_l) with G ground truth and P the estimate;
// t_err = |t(E)| / length, r_err = acos(clamp(0.5 (tr R(E) - 1), -1, 1)) / length, and the result
// is the plain mean over all segments. Segment lengths are measured in the frame the poses are
// given in (a lever arm between frames changes them slightly).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "dloam/core/types.hpp"

namespace dloam::eval {

struct SegmentOptions {
  std::vector<double> lengths = {100, 200, 300, 400, 500, 600, 700, 800};  ///< metres (devkit default)
  std::size_t step = 10;  ///< a segment starts every `step` frames (devkit: 10 = every second)
};

/// One segment of the devkit protocol.
struct SegmentError {
  std::size_t first_frame = 0;
  std::size_t last_frame = 0;
  double length = 0.0;  ///< nominal length [m]
  double t_err = 0.0;   ///< translation error / length (fraction; *100 gives %)
  double r_err = 0.0;   ///< rotation error / length [rad/m]
};

/// Mean errors of all segments of one nominal length.
struct LengthError {
  double length = 0.0;
  std::size_t count = 0;
  double t_rel_pct = 0.0;      ///< mean t_err * 100
  double r_rel_deg100m = 0.0;  ///< mean r_err in degrees per 100 m
};

struct RelativeError {
  std::vector<SegmentError> segments;
  std::vector<LengthError> per_length;  ///< one entry per length that has at least one segment
  double t_rel_pct = 0.0;               ///< mean over all segments; NaN when there is no segment
  double r_rel_deg100m = 0.0;           ///< mean over all segments; NaN when there is no segment
};

/// a^-1 * b with a general 4x4 inverse, as the devkit's Matrix::inv. Rotations read from 9-10
/// digit files are orthonormal only to ~1e-8; Isometry3d::inverse() would transpose them and leave
/// spurious rotation errors of ~1e-4 rad (sqrt of that), even when comparing a file with itself.
Pose between(const Pose& a, const Pose& b);

/// Rotation angle of a pose, by the devkit's formula acos(clamp(0.5 (trace - 1), -1, 1)) [rad].
double rotation_angle(const Pose& pose);

/// Cumulative translation between consecutive poses; dist[0] = 0.
std::vector<double> trajectory_distances(const std::vector<Pose>& poses);

/// First frame i >= first with dist[i] > dist[first] + length (strict, as the devkit), if any.
std::optional<std::size_t> last_frame_of_segment(const std::vector<double>& dist, std::size_t first,
                                                 double length);

/// All segments of the devkit protocol. Throws InputError if the sizes differ, step is 0 or a
/// length is not positive.
std::vector<SegmentError> segment_errors(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                         const SegmentOptions& options = {});

/// Segments plus their means (overall and per length).
RelativeError relative_error(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                             const SegmentOptions& options = {});

}  // namespace dloam::eval
