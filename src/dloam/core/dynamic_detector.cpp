#include "dloam/core/dynamic_detector.hpp"

namespace dloam {

double ClusterVotes::static_fraction(int cluster, int min_known) const {
  const auto c = static_cast<std::size_t>(cluster);
  if (c >= known.size() || known[c] < std::max(1, min_known)) return -1.0;
  return static_cast<double>(static_count[c]) / known[c];
}

ClusterVotes vote_clusters(const SegmentationResult& seg, const SpeedMatrix& S, double v_static,
                           double v_max) {
  const bool signs = S.behind.size() == S.speed.size();
  ClusterVotes v;
  const auto m = static_cast<std::size_t>(seg.num_clusters) + 1;
  v.known.assign(m, 0);
  v.static_count.assign(m, 0);
  for (std::size_t px = 0; px < seg.pixel_label.size(); ++px) {
    const int l = seg.pixel_label[px];
    const float s = S.speed[px];
    if (l <= 0 || s < 0.0f) continue;
    if (signs && S.behind[px] && s > v_max) continue;  // disoccluded: hidden in the previous scan
    ++v.known[static_cast<std::size_t>(l)];
    if (s < v_static) ++v.static_count[static_cast<std::size_t>(l)];
  }
  return v;
}

DetectionConfig thresholds_over(const DetectionConfig& config, double dt) {
  DetectionConfig c = config;
  c.v_static *= dt;
  c.v_ground *= dt;
  c.v_max *= dt;
  return c;
}

DetectionResult detect_dynamic(const SegmentationResult& seg, const SpeedMatrix& S,
                               const DetectionConfig& config) {
  if (S.speed.size() != seg.pixel_label.size())
    throw InputError("detect_dynamic: speed matrix of " + std::to_string(S.speed.size()) +
                     " pixels, segmentation of " + std::to_string(seg.pixel_label.size()));
  DetectionResult det;
  const ClusterVotes votes = vote_clusters(seg, S, config.v_static, config.v_max);
  det.cluster_dynamic.assign(static_cast<std::size_t>(seg.num_clusters) + 1, 0);
  det.static_fraction.assign(det.cluster_dynamic.size(), -1.0);
  for (int c = 1; c <= seg.num_clusters; ++c) {
    const double f = votes.static_fraction(c, config.N_min_dynamic);
    det.static_fraction[static_cast<std::size_t>(c)] = f;
    if (f >= 0.0 && f < config.alpha) det.cluster_dynamic[static_cast<std::size_t>(c)] = 1;
  }
  det.ground_rejected.assign(seg.pixel_label.size(), 0);
  for (std::size_t px = 0; px < seg.pixel_label.size(); ++px)
    if (seg.pixel_label[px] == kGroundLabel && S.speed[px] >= static_cast<float>(config.v_ground))
      det.ground_rejected[px] = 1;
  update_pixel_mask(seg, det);
  return det;
}

void update_pixel_mask(const SegmentationResult& seg, DetectionResult& det) {
  det.pixel_dynamic.assign(seg.pixel_label.size(), 0);
  det.num_dynamic = 0;
  for (std::size_t c = 1; c < det.cluster_dynamic.size(); ++c) det.num_dynamic += det.cluster_dynamic[c];
  for (std::size_t px = 0; px < seg.pixel_label.size(); ++px) {
    const int l = seg.pixel_label[px];
    if (l > 0 && det.cluster_dynamic[static_cast<std::size_t>(l)]) det.pixel_dynamic[px] = 1;
  }
}

std::vector<Label> point_labels(const SegmentationResult& seg, const DetectionResult& det) {
  std::vector<Label> out(seg.point_label.size(), semantic::kStatic);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const int l = seg.point_label[i];
    if (l > 0 && static_cast<std::size_t>(l) < det.cluster_dynamic.size() &&
        det.cluster_dynamic[static_cast<std::size_t>(l)])
      out[i] = semantic::make(semantic::kMovingGeneric, static_cast<std::uint32_t>(l));
  }
  return out;
}

}  // namespace dloam
