// Line + arc (+ clothoid transition) paths with continuous position and heading, and
// piecewise-linear speed profiles.
#include "dloam/sim/path.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dloam::sim {

namespace {
double heading(const Vec2& d) { return std::atan2(d.y(), d.x()); }
double wrap_angle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

/// Displacement along a spiral from heading yaw0 with curvature k0 + dk x over arc length u
/// (Fresnel-type integral; composite 4-point Gauss-Legendre, exact to ~1e-12 m for road spirals).
Vec2 spiral_displacement(double yaw0, double k0, double dk, double u) {
  static constexpr double kNode[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                      0.8611363115940526};
  static constexpr double kWeight[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                        0.3478548451374538};
  const int n = 1 + static_cast<int>(std::ceil(std::abs(u) / 2.0));
  const double h = u / n;
  Vec2 sum = Vec2::Zero();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < 4; ++j) {
      const double x = h * (i + 0.5 + 0.5 * kNode[j]);
      const double yaw = yaw0 + k0 * x + 0.5 * dk * x * x;
      sum += kWeight[j] * Vec2(std::cos(yaw), std::sin(yaw));
    }
  }
  return 0.5 * h * sum;
}

/// Distance from the start of a symmetric clothoid-arc-clothoid corner (turn theta, arc radius r,
/// transitions of length l) to the corner vertex along the incoming leg.
double corner_tangent(double theta, double r, double l) {
  if (l <= 0.0) return r * std::tan(0.5 * theta);
  const double tau = 0.5 * l / r;  // heading change of one transition
  const Vec2 e = spiral_displacement(0.0, 0.0, 1.0 / (r * l), l);
  const double shift = e.y() - r * (1.0 - std::cos(tau));  // arc centre is r + shift from the leg
  return e.x() - r * std::sin(tau) + (r + shift) * std::tan(0.5 * theta);
}

// A rounded corner at waypoint b between legs a->b and b->c.
struct Corner {
  Vec2 in, out;             ///< corner start and end points
  double yaw_in = 0.0;      ///< heading of leg a->b
  double turn = 0.0;        ///< signed turn angle
  double radius = 0.0;      ///< 0: no arc (collinear legs)
  double transition = 0.0;  ///< clothoid length at each end of the arc
};

Corner make_corner(const Vec2& a, const Vec2& b, const Vec2& c, double radius, double transition) {
  Corner k;
  const Vec2 d_in = (b - a).normalized(), d_out = (c - b).normalized();
  k.yaw_in = heading(d_in);
  k.turn = wrap_angle(heading(d_out) - k.yaw_in);
  k.in = k.out = b;
  if (std::abs(k.turn) < 1e-9 || radius <= 0.0) return k;
  const double theta = std::abs(k.turn);
  const double max_tangent = 0.5 * std::min((b - a).norm(), (c - b).norm());
  if (transition <= 0.0) {
    double tangent = radius * std::tan(0.5 * theta);
    if (tangent > max_tangent) tangent = max_tangent;
    k.radius = tangent / std::tan(0.5 * theta);
    k.in = b - tangent * d_in;
    k.out = b + tangent * d_out;
    return k;
  }
  // Two transitions turn by l / r together: a small turn is all spiral.
  k.radius = radius;
  k.transition = std::min(transition, theta * radius);
  double tangent = corner_tangent(theta, k.radius, k.transition);
  if (tangent > max_tangent) {  // the corner geometry scales with r and l together
    const double f = max_tangent / tangent;
    k.radius *= f;
    k.transition *= f;
    tangent = max_tangent;
  }
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

void Path::add_clothoid(const Vec2& start, double yaw0, double curvature, double dcurvature, double length) {
  if (length < 1e-9) return;
  segments_.push_back({start, yaw0, length_, length, curvature, dcurvature, length, 0.0});
  length_ += length;
}

void Path::add_corner(const Vec2& start, double yaw0, double turn, double radius, double transition) {
  const double k = (turn > 0 ? 1.0 : -1.0) / radius;
  if (transition <= 0.0) {
    add_arc(start, yaw0, k, radius * std::abs(turn));
    return;
  }
  auto end = [this] { return eval(segments_.back(), segments_.back().length); };
  add_clothoid(start, yaw0, 0.0, k / transition, transition);
  const PathPoint a = end();
  add_arc(a.p, a.yaw, k,
          radius * std::abs(turn) - transition);  // each spiral turns by l / 2r; skipped when ~0
  const PathPoint b = end();
  add_clothoid(b.p, b.yaw, k, -k / transition, transition);
}

Path Path::from_waypoints(const std::vector<Vec2>& waypoints, double corner_radius, bool closed,
                          double transition) {
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
      const Corner k = make_corner(w[i - 1], w[i], w[i + 1], corner_radius, transition);
      path.add_line(cursor, k.in);
      if (k.radius > 0.0) path.add_corner(k.in, k.yaw_in, k.turn, k.radius, k.transition);
      cursor = k.out;
    }
    path.add_line(cursor, w.back());
  } else {
    std::vector<Corner> corners;
    for (std::size_t i = 0; i < n; ++i)
      corners.push_back(make_corner(w[(i + n - 1) % n], w[i], w[(i + 1) % n], corner_radius, transition));
    for (std::size_t i = 0; i < n; ++i) {
      const Corner& a = corners[i];
      const Corner& b = corners[(i + 1) % n];
      path.add_line(a.out, b.in);
      if (b.radius > 0.0) path.add_corner(b.in, b.yaw_in, b.turn, b.radius, b.transition);
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
    if (it->dcurvature != 0.0) {  // the base spiral backwards, the parallel curve on the other side
      Segment base = *it;
      base.offset = 0.0;
      base.length = base.base_length;
      const PathPoint end = eval(base, base.length);
      const double k1 = it->curvature + it->dcurvature * it->base_length;
      out.segments_.push_back({end.p, end.yaw + M_PI, out.length_, it->length, -k1, it->dcurvature,
                               it->base_length, -it->offset});
      out.length_ += it->length;
      continue;
    }
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
    if (seg.dcurvature != 0.0) {
      Segment o = seg;
      o.s0 = out.length_;
      o.offset += d;
      const double k1 = seg.curvature + seg.dcurvature * seg.base_length;
      if (!(1.0 - seg.curvature * o.offset > 1e-6 && 1.0 - k1 * o.offset > 1e-6))
        throw std::invalid_argument("path: offset larger than a clothoid's radius");
      o.length = seg.base_length - o.offset * 0.5 * (seg.curvature + k1) * seg.base_length;
      out.segments_.push_back(o);
      out.length_ += o.length;
      continue;
    }
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
  for (const auto& s : out.segments_)
    out.waypoints_.push_back(s.dcurvature != 0.0 ? eval(s, 0.0).p : s.start);
  if (!closed_ && !out.segments_.empty()) out.waypoints_.push_back(out.at(out.length_).p);
  return out;
}

PathPoint Path::eval_clothoid(const Segment& seg, double s) {
  // Arc length s of the parallel curve -> u of the base spiral: s = u - offset * (k0 u + dk u^2 / 2).
  const double a = -0.5 * seg.offset * seg.dcurvature, b = 1.0 - seg.offset * seg.curvature;
  const double disc = b * b + 4.0 * a * s;
  PathPoint out;
  if (s < 0.0 || disc < 0.0) {  // before the start: straight on (only reached by open paths)
    out.yaw = seg.yaw0;
    out.p = seg.start + seg.offset * Vec2(-std::sin(out.yaw), std::cos(out.yaw)) +
            s * Vec2(std::cos(out.yaw), std::sin(out.yaw));
    return out;
  }
  const double u = 2.0 * s / (b + std::sqrt(disc));
  out.yaw = seg.yaw0 + seg.curvature * u + 0.5 * seg.dcurvature * u * u;
  out.p = seg.start + spiral_displacement(seg.yaw0, seg.curvature, seg.dcurvature, u) +
          seg.offset * Vec2(-std::sin(out.yaw), std::cos(out.yaw));
  return out;
}

PathPoint Path::eval(const Segment& seg, double u) {
  if (seg.dcurvature != 0.0) return eval_clothoid(seg, u);
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

RateProfile::RateProfile(std::vector<RateKey> keys) : keys_(std::move(keys)) {
  if (keys_.empty()) throw std::invalid_argument("rate profile: no keys");
  cumulative_.assign(keys_.size(), 0.0);
  for (std::size_t i = 0; i < keys_.size(); ++i) {
    if (!std::isfinite(keys_[i].rate) || !std::isfinite(keys_[i].t))
      throw std::invalid_argument("rate profile: key not finite");
    if (i == 0) continue;
    const double dt = keys_[i].t - keys_[i - 1].t;
    if (!(dt >= 0.0)) throw std::invalid_argument("rate profile: keys not sorted in time");
    cumulative_[i] = cumulative_[i - 1] + 0.5 * (keys_[i].rate + keys_[i - 1].rate) * dt;
  }
  offset_ = integral_from_first_key(0.0);
}

double RateProfile::rate(double t) const {
  if (t <= keys_.front().t) return keys_.front().rate;
  if (t >= keys_.back().t) return keys_.back().rate;
  auto it =
      std::upper_bound(keys_.begin(), keys_.end(), t, [](double v, const RateKey& k) { return v < k.t; });
  const RateKey& b = *it;
  const RateKey& a = *(it - 1);
  const double dt = b.t - a.t;
  return dt <= 0.0 ? b.rate : a.rate + (b.rate - a.rate) * (t - a.t) / dt;
}

double RateProfile::integral_from_first_key(double t) const {
  if (t <= keys_.front().t) return keys_.front().rate * (t - keys_.front().t);
  if (t >= keys_.back().t) return cumulative_.back() + keys_.back().rate * (t - keys_.back().t);
  auto it =
      std::upper_bound(keys_.begin(), keys_.end(), t, [](double v, const RateKey& k) { return v < k.t; });
  const auto i = static_cast<std::size_t>(it - keys_.begin()) - 1;
  return cumulative_[i] + 0.5 * (keys_[i].rate + rate(t)) * (t - keys_[i].t);
}

double RateProfile::value(double t) const { return integral_from_first_key(t) - offset_; }

double RateProfile::max_slope() const {
  double m = 0.0;
  for (std::size_t i = 1; i < keys_.size(); ++i) {
    const double dt = keys_[i].t - keys_[i - 1].t;
    if (dt > 0.0) m = std::max(m, std::abs(keys_[i].rate - keys_[i - 1].rate) / dt);
  }
  return m;
}

}  // namespace dloam::sim
