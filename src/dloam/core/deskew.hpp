// Motion-distortion removal (paper III.D.2, eq. 12): each point is moved into the sensor frame at the
// reference time of its sweep by the linearly interpolated inter-scan motion.
#pragma once

#include <vector>

#include "dloam/core/enum_names.hpp"
#include "dloam/core/se3.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// Where the per-point times of the de-skew come from.
enum class TimeSource {
  kAuto,     ///< the data's per-point time channel when present, else from the azimuth
  kAzimuth,  ///< always from the azimuth
  kNone,     ///< no time, no de-skew
};
constexpr std::array<EnumName<TimeSource>, 3> enum_names(TimeSource) {
  return {{{TimeSource::kAuto, "auto"}, {TimeSource::kAzimuth, "azimuth"}, {TimeSource::kNone, "none"}}};
}

/// III.D.2 Motion-distortion removal (eq. 12).
struct DeskewConfig {
  bool enabled = true;
  TimeSource time_source = TimeSource::kAuto;
  /// The step between two scan poses is the mean velocity between their reference times, half an
  /// interval before this sweep's: extrapolate it to the sweep's reference time with the velocity
  /// change since the step before (constant acceleration), as a turning handheld scanner needs.
  bool acceleration = true;
};

/// The sensor motion over one sweep around its reference time: the pose at sweep time tau (in
/// sweeps from the reference time) is exp(tau * xi + tau^2 / 2 * acceleration).
struct SweepMotion {
  Vec6 xi = Vec6::Zero();            ///< the twist over one sweep at the reference time
  Vec6 acceleration = Vec6::Zero();  ///< its change per sweep
  SweepMotion() = default;
  /// Constant velocity: `motion` over one sweep (implicit: a pose is a constant-velocity sweep).
  SweepMotion(const Pose& motion) : xi(log_se3(motion)) {}  // NOLINT(google-explicit-constructor)
  /// The pose change over the whole sweep at constant velocity.
  [[nodiscard]] Pose pose() const { return exp_se3(xi); }
  /// The pose at `tau` sweeps from the reference time.
  [[nodiscard]] Pose at(double tau) const { return exp_se3(tau * xi + 0.5 * tau * tau * acceleration); }
};

/// The timing of a scan: the time since the previous scan and the duration of its own sweep. A
/// sensor that drops scans still sweeps in 1 / scan_rate_hz, while the motion between the scans
/// kept spans several sweeps: the de-skew must use only the part of the step that falls in the sweep.
struct ScanInterval {
  double dt = 0.1;     ///< s since the previous scan
  double sweep = 0.1;  ///< s that this scan's sweep lasts (1 / scan_rate_hz)
  /// The velocity [w, v] (rad/s, m/s) of the step before, over `previous_dt` s (0: none known).
  /// When known, sweep_motion() extrapolates the step's velocity to this sweep's reference time.
  Vec6 previous_velocity = Vec6::Zero();
  double previous_dt = 0.0;
  /// The accelerations the platform can make (m/s^2, rad/s^2): a larger velocity change between the
  /// steps is not motion (a step after scans lost unannounced, a re-initialised step): the sweep's
  /// velocity is the previous one changed at most at these rates.
  double max_acceleration = 20.0;
  double max_angular_acceleration = 1.0;
  /// The motion over the sweep when the sensor moved by `step` over dt: at constant velocity, or at
  /// constant acceleration from previous_velocity when previous_dt > 0 (the velocity at the sweep's
  /// reference time, half an interval after the middle of the step).
  [[nodiscard]] SweepMotion sweep_motion(const Pose& step) const;
  /// Sweeps that fit in the interval beyond this one: scans lost before this scan (0 when none).
  [[nodiscard]] int missed_scans() const;
};

/// Per-point time in [0, 1) of the sweep: the data's time channel when `use_channel` and present,
/// else from the azimuth (the sweep starts at the rear and turns clockwise, see range_image.hpp).
std::vector<double> point_times(const PointCloud& cloud, bool use_channel);

/// `motion` is the sensor motion over one sweep (pose of the previous scan's reference time
/// -> this scan's, T^{k-1 -> k} expressed in the sensor frame). A point measured at time t is
/// mapped into the frame at `reference_time`: p' = linear(motion, t - reference_time) * p.
/// Times are quantised into `bins` slices so the per-point cost is one matrix product.
std::vector<Vec3> deskew(const std::vector<Vec3>& points, const std::vector<double>& times,
                         const SweepMotion& motion, double reference_time = 0.5, int bins = 256);

/// The same for the points `indices` of `points` only (e.g. the features of a scan, when a better
/// motion estimate arrives after they were extracted): equal to the whole scan's de-skew at those
/// indices.
std::vector<Vec3> deskew(const std::vector<Vec3>& points, const std::vector<double>& times,
                         const std::vector<int>& indices, const SweepMotion& motion,
                         double reference_time = 0.5, int bins = 256);

}  // namespace dloam
