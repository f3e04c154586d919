#include "dloam/pipeline/dynamic_stage.hpp"

#include "dloam/core/deskew.hpp"
#include "dloam/core/speed_matrix.hpp"
#include "dloam/core/weight_compensation.hpp"

namespace dloam {

void DynamicStage::remember_range(const RangeImage& image, const std::vector<Vec3>& points) {
  previous_range_.assign(image.range.size(), 0.0f);
  for (std::size_t px = 0; px < previous_range_.size(); ++px) {
    const int i = image.point_of_pixel[px];
    if (i >= 0) previous_range_[px] = static_cast<float>(points[static_cast<std::size_t>(i)].norm());
  }
}

CoarseResult DynamicStage::first_pair(const std::vector<Vec3>& raw, const std::vector<double>& times,
                                      const std::vector<Vec3>& deskewed, const SegmentationResult& seg,
                                      const Pose& predicted, ObjectSet& objects) {
  const PreRegistrationConfig& pre = config_.preregistration;
  // Score of a forward translation: cluster pixels that look static with it (subsampled).
  constexpr double kStep = 0.2;  // m
  const auto score = [&](const Pose& T) {
    return static_area(seg.image, deskewed, seg.pixel_label, T, previous_range_, config_.sensor, kStep, 3);
  };
  const Pose start = search_forward_translation(predicted, pre.search_range, kStep, score);
  CoarseResult c = coarse_motion(objects, *previous_objects_, start, pre);
  c.valid = true;  // the search result when the objects do not constrain the motion
  if (!times.empty() && !first_times_.empty()) {
    // Both scans de-skewed with the found motion, then the objects registered again.
    const std::vector<Vec3> first = deskew(first_raw_, first_times_, c.T);
    remember_range(first_seg_->image, first);
    ObjectSet prev = extract_objects(first, *first_seg_, pre);
    previous_objects_ = std::make_unique<FeatureMap>();
    previous_objects_->edges.build(std::move(prev.poles));
    previous_objects_->planes.build(std::move(prev.planes));
    objects = extract_objects(deskew(raw, times, c.T), seg, pre);
    const CoarseResult refined = coarse_motion(objects, *previous_objects_, c.T, pre);
    if (refined.valid) c = refined;
  }
  first_raw_ = {};
  first_times_ = {};
  first_seg_.reset();
  return c;
}

DynamicOutput DynamicStage::process(const std::vector<Vec3>& raw, const std::vector<double>& times,
                                    std::vector<Vec3> deskewed, const SegmentationResult& seg,
                                    const Pose& predicted, const std::vector<float>& intensity) {
  DynamicOutput out;
  out.T_coarse = predicted;
  const bool deskew_on = !times.empty();
  const PreRegistrationConfig& pre = config_.preregistration;
  ObjectSet objects;
  if (pre.enabled) objects = extract_objects(deskewed, seg, pre);

  // Pre-registration -> T_coarse, then the current scan de-skewed with it.
  if (have_previous_ && pre.enabled && previous_objects_) {
    const CoarseResult c = first_pair_done_ ? coarse_motion(objects, *previous_objects_, predicted, pre)
                                            : first_pair(raw, times, deskewed, seg, predicted, objects);
    out.coarse_valid = c.valid;
    out.T_coarse = c.T;
  }
  if (have_previous_) first_pair_done_ = true;
  out.points = (out.coarse_valid && deskew_on) ? deskew(raw, times, out.T_coarse) : std::move(deskewed);

  SpeedMatrix S;
  out.checked = have_previous_;
  if (have_previous_) {
    S = compute_speed_matrix(seg.image, out.points, out.T_coarse, previous_range_, config_.sensor);
  } else {
    S.speed.assign(seg.pixel_label.size(), -1.0f);
  }
  // This scan's range image with its final de-skew, for the next speed matrix (and the CNN's bags).
  remember_range(seg.image, out.points);
  DetectionResult det;
  if (cnn_) {  // III.D.3.b: the CNN on the range image bag replaces the two-frame decision
    det = cnn_->process(seg, out.points, intensity, previous_range_, out.T_coarse, config_.detection,
                        have_previous_ ? &S.speed : nullptr);
  } else if (have_previous_) {
    det = detect_dynamic(seg, S, config_.detection);
  } else {
    det.cluster_dynamic.assign(static_cast<std::size_t>(seg.num_clusters) + 1, 0);
    det.ground_rejected.assign(seg.pixel_label.size(), 0);
    update_pixel_mask(seg, det);
  }
  if (config_.detection.pseudo_static) {
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
