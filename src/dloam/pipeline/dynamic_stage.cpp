#include "dloam/pipeline/dynamic_stage.hpp"

#include "dloam/core/deskew.hpp"
#include "dloam/core/speed_matrix.hpp"
#include "dloam/core/weight_compensation.hpp"

namespace dloam {

DynamicOutput DynamicStage::process(const std::vector<Vec3>& raw, const std::vector<double>& times,
                                    std::vector<Vec3> deskewed, const SegmentationResult& seg,
                                    const Pose& predicted) {
  DynamicOutput out;
  out.T_coarse = predicted;
  const bool deskew_on = !times.empty();
  const PreRegistrationConfig& pre = config_.preregistration;
  ObjectSet objects;
  if (pre.enabled) objects = extract_objects(deskewed, seg, pre);

  // Pre-registration -> T_coarse, then the current scan de-skewed with it.
  if (have_previous_ && pre.enabled && previous_objects_) {
    const CoarseResult c = coarse_motion(objects, *previous_objects_, predicted, pre);
    out.coarse_valid = c.valid;
    out.T_coarse = c.T;
  }
  out.points = (out.coarse_valid && deskew_on) ? deskew(raw, times, out.T_coarse) : std::move(deskewed);

  DetectionResult det;
  SpeedMatrix S;
  out.checked = have_previous_;
  if (have_previous_) {
    S = compute_speed_matrix(seg.image, out.points, out.T_coarse, previous_range_, config_.sensor);
    det = detect_dynamic(seg, S, config_.detection);
  } else {
    S.speed.assign(seg.pixel_label.size(), -1.0f);
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

  // This scan's range image with its final de-skew, for the next speed matrix.
  previous_range_.assign(seg.image.range.size(), 0.0f);
  for (std::size_t px = 0; px < previous_range_.size(); ++px) {
    const int i = seg.image.point_of_pixel[px];
    if (i >= 0) previous_range_[px] = static_cast<float>(out.points[static_cast<std::size_t>(i)].norm());
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
