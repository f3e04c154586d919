#include "dloam/core/cnn_decision.hpp"

#include <string>

namespace dloam {

DetectionResult decide_from_probability(const SegmentationResult& seg, const std::vector<float>& probability,
                                        const DetectionConfig& config) {
  const std::size_t n_pix = seg.pixel_label.size();
  if (probability.size() != n_pix)
    throw InputError("decide_from_probability: " + std::to_string(probability.size()) +
                     " probabilities for a range image of " + std::to_string(n_pix) + " pixels");
  const auto thr = static_cast<float>(config.cnn_threshold);
  const auto n_clusters = static_cast<std::size_t>(seg.num_clusters) + 1;
  std::vector<int> total(n_clusters, 0), stat(n_clusters, 0);
  for (std::size_t px = 0; px < n_pix; ++px) {
    const int l = seg.pixel_label[px];
    if (l <= 0) continue;
    ++total[static_cast<std::size_t>(l)];
    if (probability[px] < thr) ++stat[static_cast<std::size_t>(l)];
  }
  DetectionResult det;
  det.cluster_dynamic.assign(n_clusters, 0);
  det.static_fraction.assign(n_clusters, -1.0);
  for (std::size_t c = 1; c < n_clusters; ++c) {
    if (total[c] == 0) continue;
    det.static_fraction[c] = static_cast<double>(stat[c]) / total[c];
    det.cluster_dynamic[c] = det.static_fraction[c] < config.alpha ? 1 : 0;
  }
  det.ground_rejected.assign(n_pix, 0);
  for (std::size_t px = 0; px < n_pix; ++px)
    if (seg.pixel_label[px] == kGroundLabel && probability[px] >= thr) det.ground_rejected[px] = 1;
  update_pixel_mask(seg, det);
  return det;
}

}  // namespace dloam
