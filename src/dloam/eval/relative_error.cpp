// KITTI devkit relative error (evaluate_odometry.cpp: trajectoryDistances,
// lastFrameFromSegmentLength, calcSequenceErrors, saveStats), in double precision.
#include "dloam/eval/relative_error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace dloam::eval {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

std::string number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void check_inputs(const std::vector<Pose>& gt, const std::vector<Pose>& est, const SegmentOptions& options) {
  if (gt.size() != est.size()) {
    throw InputError("relative error: ground truth has " + std::to_string(gt.size()) +
                     " poses but the estimate has " + std::to_string(est.size()));
  }
  if (options.step == 0) throw InputError("relative error: segment step must be at least 1 frame");
  for (std::size_t i = 0; i < options.lengths.size(); ++i) {
    const double length = options.lengths[i];
    if (!(length > 0.0) || !std::isfinite(length)) {
      throw InputError("relative error: segment length " + number(length) + " m is not positive");
    }
    if (std::find(options.lengths.begin(), options.lengths.begin() + i, length) !=
        options.lengths.begin() + i) {
      throw InputError("relative error: segment length " + number(length) + " m is given twice");
    }
  }
}

}  // namespace

Pose between(const Pose& a, const Pose& b) {
  Pose result;
  result.matrix() = a.matrix().inverse() * b.matrix();
  return result;
}

double rotation_angle(const Pose& pose) {
  const double d = 0.5 * (pose.linear().trace() - 1.0);
  return std::acos(std::clamp(d, -1.0, 1.0));
}

std::vector<double> trajectory_distances(const std::vector<Pose>& poses) {
  std::vector<double> dist;
  dist.reserve(poses.size());
  if (!poses.empty()) dist.push_back(0.0);
  for (std::size_t i = 1; i < poses.size(); ++i) {
    dist.push_back(dist.back() + (poses[i].translation() - poses[i - 1].translation()).norm());
  }
  return dist;
}

std::optional<std::size_t> last_frame_of_segment(const std::vector<double>& dist, std::size_t first,
                                                 double length) {
  for (std::size_t i = first; i < dist.size(); ++i) {
    if (dist[i] > dist[first] + length) return i;
  }
  return std::nullopt;
}

std::vector<SegmentError> segment_errors(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                         const SegmentOptions& options) {
  check_inputs(gt, est, options);
  const std::vector<double> dist = trajectory_distances(gt);
  std::vector<SegmentError> segments;
  for (std::size_t first = 0; first < gt.size(); first += options.step) {
    for (const double length : options.lengths) {
      const std::optional<std::size_t> last = last_frame_of_segment(dist, first, length);
      if (!last) continue;
      const Pose error = between(between(est[first], est[*last]), between(gt[first], gt[*last]));
      segments.push_back(
          {first, *last, length, error.translation().norm() / length, rotation_angle(error) / length});
    }
  }
  return segments;
}

RelativeError relative_error(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                             const SegmentOptions& options) {
  RelativeError result;
  result.segments = segment_errors(gt, est, options);
  const auto mean_of = [](const std::vector<const SegmentError*>& segments, LengthError& out) {
    double t_sum = 0.0, r_sum = 0.0;
    for (const SegmentError* s : segments) {
      t_sum += s->t_err;
      r_sum += s->r_err;
    }
    const double n = static_cast<double>(segments.size());
    out.count = segments.size();
    out.t_rel_pct = segments.empty() ? std::numeric_limits<double>::quiet_NaN() : 100.0 * t_sum / n;
    out.r_rel_deg100m =
        segments.empty() ? std::numeric_limits<double>::quiet_NaN() : 100.0 * kRadToDeg * r_sum / n;
  };
  std::vector<const SegmentError*> all;
  for (const SegmentError& s : result.segments) all.push_back(&s);
  LengthError overall;
  mean_of(all, overall);
  result.t_rel_pct = overall.t_rel_pct;
  result.r_rel_deg100m = overall.r_rel_deg100m;
  for (const double length : options.lengths) {
    std::vector<const SegmentError*> of_length;
    for (const SegmentError& s : result.segments) {
      if (s.length == length) of_length.push_back(&s);
    }
    if (of_length.empty()) continue;
    LengthError entry;
    entry.length = length;
    mean_of(of_length, entry);
    result.per_length.push_back(entry);
  }
  return result;
}

}  // namespace dloam::eval
