#include "dloam/pipeline/dynamic_stage.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "dloam/core/deskew.hpp"
#include "dloam/core/range_image.hpp"
#include "dloam/core/speed_matrix.hpp"
#include "dloam/core/weight_compensation.hpp"
#include "dloam/pipeline/step_fit.hpp"

namespace dloam {

namespace {
constexpr double kDeg = M_PI / 180.0;
}  // namespace

void DynamicStage::remember_range(const RangeImage& image, const std::vector<Vec3>& points) {
  // Columns from the final de-skew: the segmentation assigned the pixels before it, and at speed
  // the de-skew moves points by more than a column (2.5 m per sweep at 90 km/h). The rows stay
  // (the de-skew barely changes a point's elevation). The nearest point of a pixel wins.
  const auto n = static_cast<int>(points.size());
  std::vector<int>& pixel = pixel_scratch_;
  pixel.assign(points.size(), -1);
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 8192), [&](const tbb::blocked_range<int>& range) {
    for (int i = range.begin(); i < range.end(); ++i) {
      const int row = image.row_of_point[static_cast<std::size_t>(i)];
      const Vec3& p = points[static_cast<std::size_t>(i)];
      if (row >= 0)
        pixel[static_cast<std::size_t>(i)] = image.pixel(row, azimuth_column(p.x(), p.y(), image.cols));
    }
  });
  fill_vertex_map(points, pixel, image.rows, image.cols, previous_vertices_);
}

CoarseResult DynamicStage::first_pair(const std::vector<Vec3>& raw, const std::vector<double>& times,
                                      const std::vector<Vec3>& deskewed, const SegmentationResult& seg,
                                      const StepPrior& prior, ObjectSet& objects) {
  const PreRegistrationConfig& pre = config_.preregistration;
  // Score of a forward translation: cluster pixels that look static with it (subsampled), with a
  // static threshold matching the step. A coarse search, then a fine one around its best: an
  // error of half a coarse step already exceeds v_static on surfaces facing the motion.
  const std::vector<int> scored = static_area_pixels(seg.image, deskewed, seg.pixel_label, 3);
  const auto score_with = [&](double v) {
    return [&, v](const Pose& T) {
      return static_area(seg.image, deskewed, scored, T, previous_vertices_.range, config_.sensor, v);
    };
  };
  // Turns too, within what the platform can turn over the interval: coarse (the static threshold
  // of the coarse steps), then around the best.
  constexpr double kCoarseStep = 0.4;         // m
  constexpr double kCoarseTurn = 2.0 * kDeg;  // rad: 0.35 m at 10 m
  constexpr double kStep = 0.2;               // m
  constexpr double kTurn = 0.5 * kDeg;        // rad
  constexpr double kFineStep = 0.04;          // m
  // Scans dropped before the second one widen the ranges with the interval: past kMaxCandidates
  // the coarse level starts coarser and comes down (a 4 s gap: 200 k candidates at these steps).
  constexpr std::size_t kMaxCandidates = 4000;
  Pose start = prior.predicted;
  if (prior.yaw_range > 0.0) {
    start = search_planar_motion_bounded(start, prior.search_range, kCoarseStep, prior.yaw_range, kCoarseTurn,
                                         kMaxCandidates, score_with);
    start = search_planar_motion(start, kCoarseStep, kStep, kCoarseTurn, kTurn, score_with(kStep));
  } else {
    start =
        search_planar_motion_bounded(start, prior.search_range, kStep, 0.0, 0.0, kMaxCandidates, score_with);
  }
  start = search_forward_translation(start, kStep, kFineStep, score_with(kFineStep));
  // The search result is no motion prior: the object ICP may move far from it (no motion gate).
  CoarseResult c = coarse_motion(objects, *previous_objects_, start, pre, nullptr);
  c.valid = true;  // the search result when the objects do not constrain the motion
  if (!times.empty() && !first_times_.empty()) {
    // Both scans de-skewed with the found motion, then the objects registered again.
    const std::vector<Vec3> first = deskew(first_raw_, first_times_, prior.interval.sweep_motion(c.T));
    remember_range(first_seg_->image, first);
    ObjectSet prev = extract_objects(first, *first_seg_, pre);
    previous_objects_ = std::make_unique<FeatureMap>();
    previous_objects_->edges.build(std::move(prev.poles));
    previous_objects_->planes.build(std::move(prev.planes));
    objects = extract_objects(deskew(raw, times, prior.interval.sweep_motion(c.T)), seg, pre);
    const CoarseResult refined = coarse_motion(objects, *previous_objects_, c.T, pre, nullptr);
    if (refined.valid) c = refined;
  }
  std::vector<Vec3>().swap(first_raw_);
  std::vector<double>().swap(first_times_);
  first_seg_.reset();
  return c;
}

namespace {
/// Every cluster static, no ground rejected.
DetectionResult no_dynamic(const SegmentationResult& seg) {
  DetectionResult det;
  det.cluster_dynamic.assign(static_cast<std::size_t>(seg.num_clusters) + 1, 0);
  det.static_fraction.assign(det.cluster_dynamic.size(), -1.0);
  det.ground_rejected.assign(seg.pixel_label.size(), 0);
  update_pixel_mask(seg, det);
  return det;
}
}  // namespace

DynamicOutput DynamicStage::process(const std::vector<Vec3>& raw, const std::vector<double>& times,
                                    std::vector<Vec3> deskewed, const SegmentationResult& seg,
                                    const StepPrior& prior, const std::vector<float>& intensity) {
  DynamicOutput out;
  const Pose& predicted = prior.predicted;
  out.T_coarse = predicted;
  const bool deskew_on = !times.empty();
  const PreRegistrationConfig& pre = config_.preregistration;
  ObjectSet objects;
  if (pre.enabled) objects = extract_objects(deskewed, seg, pre);

  // Pre-registration -> T_coarse, then the current scan de-skewed with it.
  const bool first_pair_now = have_previous_ && !first_pair_done_;
  if (have_previous_ && pre.enabled && previous_objects_) {
    const CoarseResult c = first_pair_now
                               ? first_pair(raw, times, deskewed, seg, prior, objects)
                               : coarse_motion(objects, *previous_objects_, predicted, pre, &prior.gate);
    out.coarse_valid = c.valid;
    out.T_coarse = c.T;
  }
  if (have_previous_ && pre.enabled && pre.refine) {
    // The refined motion must pass the motion gate around the prediction (around T_coarse for the
    // first pair, which has no prediction): beyond it, it found another surface, not a better motion.
    const AlignmentResult a = align_range_images(deskewed, seg.image.point_of_pixel, previous_vertices_,
                                                 config_.sensor, out.T_coarse);
    if (a.valid && prior.gate.admits((first_pair_now ? out.T_coarse : predicted).inverse() * a.T)) {
      out.T_coarse = a.T;
      out.coarse_valid = true;
    }
  }
  if (have_previous_) first_pair_done_ = true;
  out.points = (out.coarse_valid && deskew_on) ? deskew(raw, times, prior.interval.sweep_motion(out.T_coarse))
                                               : std::move(deskewed);
  // The speeds are range changes over dt: the thresholds (m/s) become metres over this interval.
  const DetectionConfig detection = thresholds_over(config_.detection, prior.interval.dt);

  // A step the prediction and pre-registration got wrong (a fast turn, a sudden stop) makes the static
  // scene look moving: below the fit that recent steps reached, the speed matrix measures the
  // registration error, and the detection sits this scan out (the odometry then uses every feature).
  if (have_previous_ && prior.previous_range && prior.probe && prior.min_fit > 0.0 &&
      prior.previous_range->size() == seg.image.range.size()) {
    const double fit =
        step_fit(seg, out.points, *prior.probe, out.T_coarse, *prior.previous_range, config_.sensor);
    out.suspended = fit < prior.min_fit;
  }
  SpeedMatrix S;  // only a detection that runs reads it
  out.checked = have_previous_;
  if (have_previous_ && !out.suspended) {
    S = compute_speed_matrix(seg.image, out.points, out.T_coarse, previous_vertices_.range, config_.sensor);
  } else {
    S.speed.assign(seg.pixel_label.size(), -1.0f);
  }
  // This scan's range image with its final de-skew, for the next speed matrix (and the CNN's bags).
  remember_range(seg.image, out.points);
  DetectionResult det;
  if (out.suspended) {
    det = no_dynamic(seg);
  } else if (cnn_ && cnn_->ready()) {
    // III.D.3.b: the CNN on the range image bag replaces the two-frame decision.
    det = cnn_->process(seg, out.points, intensity, previous_vertices_.range, out.T_coarse, detection,
                        have_previous_ ? &S.speed : nullptr);
  } else if (have_previous_) {
    // The geometric detector, also for the CNN's first m scans: their bags lack speed images, and
    // a drive's first motion must not lock onto co-moving traffic.
    det = detect_dynamic(seg, S, detection);
  } else {
    det = no_dynamic(seg);
  }
  // The CNN's history keeps every scan, also those it did not see (its first m, suspended ones).
  if (cnn_ && (out.suspended || !cnn_->ready())) cnn_->remember(previous_vertices_.range, out.T_coarse);
  // The tracker associates clusters through the speed matrix's pixels: after a suspended scan it
  // starts again.
  if (out.suspended) tracker_ = ObjectTracker{};
  if (config_.detection.pseudo_static && !out.suspended) {
    TrackResult track = tracker_.update(seg, S, det, config_.detection.alpha_tracked);
    out.type1 = track.type1;
    out.type2 = track.type2;
    out.mask.pseudo_static = std::move(track.pseudo_static);
  }
  out.num_dynamic = det.num_dynamic;
  out.mask.excluded.resize(seg.pixel_label.size());
  for (std::size_t px = 0; px < out.mask.excluded.size(); ++px)
    out.mask.excluded[px] = det.pixel_dynamic[px] | det.ground_rejected[px];
  out.labels = point_labels(seg, det);
  out.column_distance = dynamic_column_distance(det.pixel_dynamic, seg.image.rows, seg.image.cols);

  if (!have_previous_ && pre.enabled) {
    first_raw_ = raw;
    first_times_ = times;
    first_seg_ = std::make_unique<SegmentationResult>(seg);
  }
  if (pre.enabled) {
    previous_objects_ = std::make_unique<FeatureMap>();
    previous_objects_->edges.build(std::move(objects.poles));
    previous_objects_->planes.build(std::move(objects.planes));
  }
  have_previous_ = true;
  return out;
}

}  // namespace dloam
