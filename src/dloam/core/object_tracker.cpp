#include "dloam/core/object_tracker.hpp"

namespace dloam {

namespace {
/// The hysteresis holds only objects detected dynamic in this many consecutive scans (a single
/// false detection of a static cluster is not carried on).
constexpr int kConfirmedScans = 2;
}  // namespace

TrackResult ObjectTracker::update(const SegmentationResult& seg, const SpeedMatrix& S, DetectionResult& det,
                                  double alpha_tracked) {
  const auto m = static_cast<std::size_t>(seg.num_clusters) + 1;
  TrackResult out;
  out.previous_cluster.assign(m, 0);
  out.transition.assign(m, Transition::kNone);
  out.pseudo_static.assign(seg.pixel_label.size(), 0);
  age_.assign(m, 0);
  const bool have_previous = previous_pixel_label_.size() == seg.pixel_label.size() &&
                             S.previous_pixel.size() == seg.pixel_label.size();
  if (have_previous) {
    // Majority vote (Boyer-Moore, one pass) of the previous cluster under each current cluster's pixels.
    std::vector<int> candidate(m, 0), count(m, 0);
    for (std::size_t px = 0; px < seg.pixel_label.size(); ++px) {
      const int l = seg.pixel_label[px];
      const int pp = S.previous_pixel[px];
      if (l <= 0 || pp < 0) continue;
      const int prev = previous_pixel_label_[static_cast<std::size_t>(pp)];
      if (prev <= 0) continue;
      const auto c = static_cast<std::size_t>(l);
      if (count[c] == 0) candidate[c] = prev;
      count[c] += candidate[c] == prev ? 1 : -1;
    }
    for (std::size_t c = 1; c < m; ++c) {
      const int best = candidate[c];
      out.previous_cluster[c] = best;
      if (best <= 0 || static_cast<std::size_t>(best) >= previous_age_.size()) continue;
      const int age = previous_age_[static_cast<std::size_t>(best)];
      const bool was = age > 0;
      const double f = c < det.static_fraction.size() ? det.static_fraction[c] : -1.0;
      if (age >= kConfirmedScans && !det.cluster_dynamic[c] && f >= 0.0 && f < alpha_tracked)
        det.cluster_dynamic[c] = 1;
      const bool is = det.cluster_dynamic[c] != 0;
      if (is) age_[c] = age + 1;
      if (!was && is) out.transition[c] = Transition::kStaticToDynamic, ++out.type1;
      if (was && !is) out.transition[c] = Transition::kDynamicToStatic, ++out.type2;
    }
    update_pixel_mask(seg, det);
    for (std::size_t px = 0; px < seg.pixel_label.size(); ++px) {
      const int l = seg.pixel_label[px];
      if (l > 0 && out.transition[static_cast<std::size_t>(l)] == Transition::kDynamicToStatic)
        out.pseudo_static[px] = 1;
    }
  }
  for (std::size_t c = 1; c < m; ++c)
    if (det.cluster_dynamic[c] && age_[c] == 0) age_[c] = 1;
  previous_pixel_label_ = seg.pixel_label;
  std::swap(previous_age_, age_);
  return out;
}

}  // namespace dloam
