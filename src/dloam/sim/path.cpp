// Line + arc paths (continuous position and heading) and piecewise-linear speed profiles.
#include "dloam/sim/path.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dloam::sim {

namespace {
double heading(const Vec2& d) { return std::atan2(d.y(), d.x()); }
double wrap_angle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// A rounded corner at waypoint b between legs a->b and b->c.
struct Corner {
  Vec2 in, out;         ///< arc start and end points
  double yaw_in = 0.0;  ///< heading of leg a->b
  double turn = 0.0;    ///< signed turn angle
  double radius = 0.0;  ///< 0: no arc (collinear legs)
};

Corner make_corner(const Vec2& a, const Vec2& b, const Vec2& c, double radius) {
  Corner k;
  const Vec2 d_in = (b - a).normalized(), d_out = (c - b).normalized();
  k.yaw_in = heading(d_in);
  k.turn = wrap_angle(heading(d_out) - k.yaw_in);
  k.in = k.out = b;
  if (std::abs(k.turn) < 1e-9 || radius <= 0.0) return k;
  double tangent = radius * std::tan(0.5 * std::abs(k.turn));
  const double max_tangent = 0.5 * std::min((b - a).norm(), (c - b).norm());
  if (tangent > max_tangent) tangent = max_tangent;
  k.radius = tangent / std::tan(0.5 * std::abs(k.turn));
  k.in = b - tangent * d_in;
  k.out = b + tangent * d_out;
  return k;
}
}  // namespace

void Path::add_line(const Vec2& a, const Vec2& b) {
  const double len = (b - a).norm();
  if (len < 1e-9) return;
  segments_.push_back({a, heading(b - a), length_, len, 0.0});
  length_ += len;
}

void Path::add_arc(const Vec2& start, double yaw0, double curvature, double length) {
  if (length < 1e-9) return;
  segments_.push_back({start, yaw0, length_, length, curvature});
  length_ += length;
}

Path Path::from_waypoints(const std::vector<Vec2>& waypoints, double corner_radius, bool closed) {
  std::vector<Vec2> w;
  for (const auto& p : waypoints)
    if (w.empty() || (p - w.back()).norm() > 1e-6) w.push_back(p);
  if (closed && w.size() > 1 && (w.front() - w.back()).norm() < 1e-6) w.pop_back();
  if (w.size() < 2 || (closed && w.size() < 3))
    throw std::invalid_argument("path: need at least 2 distinct waypoints (3 for a closed path)");
  Path path;
  path.waypoints_ = w;
  path.corner_radius_ = corner_radius;
  path.closed_ = closed;
  const std::size_t n = w.size();
  if (!closed) {
    Vec2 cursor = w.front();
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const Corner k = make_corner(w[i - 1], w[i], w[i + 1], corner_radius);
      path.add_line(cursor, k.in);
      if (k.radius > 0.0)
        path.add_arc(k.in, k.yaw_in, (k.turn > 0 ? 1.0 : -1.0) / k.radius, k.radius * std::abs(k.turn));
      cursor = k.out;
    }
    path.add_line(cursor, w.back());
  } else {
    std::vector<Corner> corners;
    for (std::size_t i = 0; i < n; ++i)
      corners.push_back(make_corner(w[(i + n - 1) % n], w[i], w[(i + 1) % n], corner_radius));
    for (std::size_t i = 0; i < n; ++i) {
      const Corner& a = corners[i];
      const Corner& b = corners[(i + 1) % n];
      path.add_line(a.out, b.in);
      if (b.radius > 0.0)
        path.add_arc(b.in, b.yaw_in, (b.turn > 0 ? 1.0 : -1.0) / b.radius, b.radius * std::abs(b.turn));
    }
  }
  return path;
}

Path Path::reversed() const {
  Path out;
  out.closed_ = closed_;
  out.corner_radius_ = corner_radius_;
  out.waypoints_.assign(waypoints_.rbegin(), waypoints_.rend());
  for (auto it = segments_.rbegin(); it != segments_.rend(); ++it) {
    const PathPoint end = eval(*it, it->length);
    out.segments_.push_back({end.p, end.yaw + M_PI, out.length_, it->length, -it->curvature});
    out.length_ += it->length;
  }
  return out;
}

Path Path::offset(double d) const {
  Path out;
  out.closed_ = closed_;
  out.corner_radius_ = corner_radius_;
  for (const auto& seg : segments_) {
    const double scale = 1.0 - seg.curvature * d;
    if (!(scale > 1e-6)) throw std::invalid_argument("path: offset larger than an arc radius");
    const Vec2 start = seg.start + d * Vec2(-std::sin(seg.yaw0), std::cos(seg.yaw0));
    if (seg.curvature == 0.0) {
      out.segments_.push_back({start, seg.yaw0, out.length_, seg.length, 0.0});
    } else {
      out.segments_.push_back({start, seg.yaw0, out.length_, seg.length * scale, seg.curvature / scale});
    }
    out.length_ += out.segments_.back().length;
  }
  for (const auto& s : out.segments_) out.waypoints_.push_back(s.start);
  if (!closed_ && !out.segments_.empty()) out.waypoints_.push_back(out.at(out.length_).p);
  return out;
}

PathPoint Path::eval(const Segment& seg, double u) {
  PathPoint out;
  if (seg.curvature == 0.0) {
    out.yaw = seg.yaw0;
    out.p = seg.start + u * Vec2(std::cos(seg.yaw0), std::sin(seg.yaw0));
    return out;
  }
  out.yaw = seg.yaw0 + seg.curvature * u;
  out.p = seg.start + Vec2(std::sin(out.yaw) - std::sin(seg.yaw0), std::cos(seg.yaw0) - std::cos(out.yaw)) /
                          seg.curvature;
  return out;
}

PathPoint Path::at(double s) const {
  if (segments_.empty()) return {};
  if (closed_) {
    s = std::fmod(s, length_);
    if (s < 0.0) s += length_;
  }
  if (s <= 0.0) return eval(segments_.front(), s);  // straight extrapolation before the start
  auto it = std::upper_bound(segments_.begin(), segments_.end(), s,
                             [](double v, const Segment& seg) { return v < seg.s0; });
  const Segment& seg = *(it - 1);
  const bool beyond_end = (it == segments_.end()) && s > seg.s0 + seg.length;
  if (!beyond_end) return eval(seg, s - seg.s0);
  PathPoint end = eval(seg, seg.length);  // straight extrapolation after the end
  end.p += (s - seg.s0 - seg.length) * Vec2(std::cos(end.yaw), std::sin(end.yaw));
  return end;
}

SpeedProfile::SpeedProfile(std::vector<SpeedKey> keys) : keys_(std::move(keys)) {
  if (keys_.empty()) throw std::invalid_argument("speed profile: no keys");
  cumulative_.assign(keys_.size(), 0.0);
  for (std::size_t i = 0; i < keys_.size(); ++i) {
    if (!(keys_[i].v >= 0.0)) throw std::invalid_argument("speed profile: negative speed");
    if (i == 0) continue;
    const double dt = keys_[i].t - keys_[i - 1].t;
    if (!(dt >= 0.0)) throw std::invalid_argument("speed profile: keys not sorted in time");
    cumulative_[i] = cumulative_[i - 1] + 0.5 * (keys_[i].v + keys_[i - 1].v) * dt;
  }
  offset_ = distance_from_first_key(0.0);
}

double SpeedProfile::speed(double t) const {
  if (t <= keys_.front().t) return keys_.front().v;
  if (t >= keys_.back().t) return keys_.back().v;
  auto it =
      std::upper_bound(keys_.begin(), keys_.end(), t, [](double v, const SpeedKey& k) { return v < k.t; });
  const SpeedKey& b = *it;
  const SpeedKey& a = *(it - 1);
  const double dt = b.t - a.t;
  return dt <= 0.0 ? b.v : a.v + (b.v - a.v) * (t - a.t) / dt;
}

double SpeedProfile::distance_from_first_key(double t) const {
  if (t <= keys_.front().t) return keys_.front().v * (t - keys_.front().t);
  if (t >= keys_.back().t) return cumulative_.back() + keys_.back().v * (t - keys_.back().t);
  auto it =
      std::upper_bound(keys_.begin(), keys_.end(), t, [](double v, const SpeedKey& k) { return v < k.t; });
  const auto i = static_cast<std::size_t>(it - keys_.begin()) - 1;
  return cumulative_[i] + 0.5 * (keys_[i].v + speed(t)) * (t - keys_[i].t);
}

double SpeedProfile::distance(double t) const { return distance_from_first_key(t) - offset_; }

}  // namespace dloam::sim
