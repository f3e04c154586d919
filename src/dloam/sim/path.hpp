// Motion along a planar path: a Path of straight lines joined by circular arcs (continuous
// heading), parametrised by arc length, and a SpeedProfile giving the distance travelled along
// it as a function of time (piecewise-linear speed, so stop-and-go motion is smooth). A
// RateProfile is the signed counterpart (e.g. a yaw rate and the heading it integrates to).
// Realism: a car cannot switch from straight to full steering lock instantly, so corners can have
// clothoid transitions (curvature linear in arc length, the road-design spiral): at constant speed
// v the yaw rate then ramps up and down with a bounded yaw acceleration v^2 / (R L) instead of
// jumping to v / R. A line-arc-line corner has a yaw-rate step that no real drive has (and that a
// LiDAR's constant-velocity de-skew cannot represent).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace dloam::sim {

using Vec2 = Eigen::Vector2d;

/// Position and heading (rad, counter-clockwise from +x) on a path.
struct PathPoint {
  Vec2 p = Vec2::Zero();
  double yaw = 0.0;
};

class Path {
 public:
  Path() = default;
  /// Polyline through `waypoints` with corners rounded by arcs of `corner_radius` (smaller when
  /// the legs are short). A closed path also rounds the corner at the first waypoint and starts
  /// (s = 0) right after it. `transition` > 0: each arc is entered and left through clothoids of
  /// that length (shorter when the turn is too small for two; radius and transition shrink together
  /// when the legs are short). Throws std::invalid_argument for fewer than 2 distinct waypoints.
  static Path from_waypoints(const std::vector<Vec2>& waypoints, double corner_radius, bool closed,
                             double transition = 0.0);
  /// Pose at arc length s. Closed paths wrap around; open paths continue straight beyond their ends.
  [[nodiscard]] PathPoint at(double s) const;
  [[nodiscard]] double length() const { return length_; }
  [[nodiscard]] bool closed() const { return closed_; }
  /// Corner points the path was built from (segment starts for an offset path).
  [[nodiscard]] const std::vector<Vec2>& waypoints() const { return waypoints_; }
  /// The same curve traversed backwards.
  [[nodiscard]] Path reversed() const;
  /// The parallel curve `d` metres to the left (negative: right), arcs keep their centres.
  /// Throws std::invalid_argument when an arc's (or clothoid's) radius is not larger than |d| on
  /// its inner side.
  [[nodiscard]] Path offset(double d) const;

 private:
  struct Segment {
    Vec2 start;
    double yaw0 = 0.0;
    double s0 = 0.0;
    double length = 0.0;
    double curvature = 0.0;  ///< 1/radius, positive turning left; 0 for a line
    // Clothoids only (dcurvature != 0): curvature(u) = curvature + dcurvature * u along the base
    // spiral of length `base_length` from `start`; the segment is that spiral's parallel curve
    // `offset` metres to the left, and `length` is the parallel curve's own arc length.
    double dcurvature = 0.0;
    double base_length = 0.0;
    double offset = 0.0;
  };
  void add_line(const Vec2& a, const Vec2& b);
  void add_arc(const Vec2& start, double yaw0, double curvature, double length);
  void add_clothoid(const Vec2& start, double yaw0, double curvature, double dcurvature, double length);
  /// A rounded corner (clothoid, arc, clothoid) from `start` with heading `yaw0`.
  void add_corner(const Vec2& start, double yaw0, double turn, double radius, double transition);
  [[nodiscard]] static PathPoint eval(const Segment& seg, double u);
  [[nodiscard]] static PathPoint eval_clothoid(const Segment& seg, double u);

  std::vector<Segment> segments_;
  std::vector<Vec2> waypoints_;
  double corner_radius_ = 0.0;
  double length_ = 0.0;
  bool closed_ = false;
};

/// Speed keyframe: speed v (m/s) at time t (s); the speed is linear between keys and constant
/// before the first and after the last.
struct SpeedKey {
  double t = 0.0;
  double v = 0.0;
};

class SpeedProfile {
 public:
  SpeedProfile() : SpeedProfile(std::vector<SpeedKey>{{0.0, 0.0}}) {}
  /// Throws std::invalid_argument when empty, unsorted in time, or with a negative speed.
  explicit SpeedProfile(std::vector<SpeedKey> keys);
  static SpeedProfile constant(double v) { return SpeedProfile({{0.0, v}}); }
  [[nodiscard]] double speed(double t) const;
  /// Distance travelled from time 0 to t (negative for t < 0).
  [[nodiscard]] double distance(double t) const;
  [[nodiscard]] const std::vector<SpeedKey>& keys() const { return keys_; }

 private:
  [[nodiscard]] double distance_from_first_key(double t) const;
  std::vector<SpeedKey> keys_;
  std::vector<double> cumulative_;  ///< distance from the first key to each key
  double offset_ = 0.0;             ///< distance_from_first_key(0)
};

/// Rate keyframe: rate (any sign, e.g. rad/s) at time t (s).
struct RateKey {
  double t = 0.0;
  double rate = 0.0;
};

/// A signed rate, linear between keys and constant before the first and after the last, and its
/// integral from time 0: the rate is continuous and changes at most by the steepest key slope per
/// second (for a yaw rate: a bounded angular acceleration).
class RateProfile {
 public:
  RateProfile() : RateProfile(std::vector<RateKey>{{0.0, 0.0}}) {}
  /// Throws std::invalid_argument when empty, unsorted in time or not finite.
  explicit RateProfile(std::vector<RateKey> keys);
  static RateProfile constant(double rate) { return RateProfile({{0.0, rate}}); }
  [[nodiscard]] double rate(double t) const;
  /// Integral of the rate from time 0 to t (negative of the integral from t to 0 for t < 0).
  [[nodiscard]] double value(double t) const;
  /// Largest |d rate / dt| between keys.
  [[nodiscard]] double max_slope() const;
  [[nodiscard]] const std::vector<RateKey>& keys() const { return keys_; }

 private:
  [[nodiscard]] double integral_from_first_key(double t) const;
  std::vector<RateKey> keys_;
  std::vector<double> cumulative_;
  double offset_ = 0.0;
};

}  // namespace dloam::sim
