#include "dloam/core/range_image_bag.hpp"

#include <algorithm>

#include "dloam/core/speed_matrix.hpp"

namespace dloam {

RangeImageBag make_range_image_bag(const RangeImage& image, const std::vector<Vec3>& points,
                                   const std::vector<float>& intensity, const Pose& pose,
                                   const std::vector<const PastScan*>& past, int m,
                                   const SensorConfig& sensor, const std::vector<float>* speed1) {
  RangeImageBag out;
  out.channels = bag_channels(m);
  out.rows = image.rows;
  out.cols = image.cols;
  const int n_pix = image.rows * image.cols;
  out.data.assign(static_cast<std::size_t>(out.channels) * static_cast<std::size_t>(n_pix), 0.0f);
  for (int px = 0; px < n_pix; ++px) {
    const int i = image.point_of_pixel[static_cast<std::size_t>(px)];
    if (i < 0) continue;
    const Vec3& p = points[static_cast<std::size_t>(i)];
    out.at(kBagRange, px) = image.range[static_cast<std::size_t>(px)] * kBagMetricScale;
    out.at(kBagX, px) = static_cast<float>(p.x()) * kBagMetricScale;
    out.at(kBagY, px) = static_cast<float>(p.y()) * kBagMetricScale;
    out.at(kBagZ, px) = static_cast<float>(p.z()) * kBagHeightScale;
    if (!intensity.empty()) out.at(kBagIntensity, px) = intensity[static_cast<std::size_t>(i)];
  }
  for (int j = 1; j <= m; ++j) {
    const int c = kBagSpeed + j - 1;
    if (static_cast<std::size_t>(j) > past.size()) {  // not enough history yet: unknown
      for (int px = 0; px < n_pix; ++px)
        if (image.point_of_pixel[static_cast<std::size_t>(px)] >= 0) out.at(c, px) = kBagSpeedUnknown;
      continue;
    }
    SpeedMatrix S;
    if (j > 1 || !speed1) {
      const PastScan& f = *past[static_cast<std::size_t>(j - 1)];
      S = compute_speed_matrix(image, points, f.pose.inverse() * pose, f.range, sensor);
    }
    const std::vector<float>& speed = j == 1 && speed1 ? *speed1 : S.speed;
    for (int px = 0; px < n_pix; ++px) {
      if (image.point_of_pixel[static_cast<std::size_t>(px)] < 0) continue;
      const float s = speed[static_cast<std::size_t>(px)];
      out.at(c, px) = s < 0.0f ? kBagSpeedUnknown : std::min(s, kBagSpeedClip);
    }
  }
  return out;
}

RangeImageBag ScanHistory::bag(const RangeImage& image, const std::vector<Vec3>& points,
                               const std::vector<float>& intensity, const Pose& pose,
                               const std::vector<float>* speed1) const {
  std::vector<const PastScan*> past;
  for (const PastScan& f : frames_) past.push_back(&f);
  return make_range_image_bag(image, points, intensity, pose, past, m_, sensor_, speed1);
}

void ScanHistory::push(std::vector<float> range, const Pose& pose) {
  if (m_ <= 0) return;
  frames_.push_front({std::move(range), pose});
  while (frames_.size() > static_cast<std::size_t>(m_)) frames_.pop_back();
}

void ScanHistory::set_latest_pose(const Pose& pose) {
  if (!frames_.empty()) frames_.front().pose = pose;
}

}  // namespace dloam
