// The CNN's input (paper III.D.3.b, Fig. 4): a "range image bag" made of the current range image
// (range, x, y, z, intensity per pixel) and m speed images of the current scan against the m most
// recent scans. Speed image j is eq. 13's speed matrix between scan k and scan k-j, computed with
// the pipeline's own poses (compute_speed_matrix: the current pixel's point moved into scan k-j's
// frame against that scan's range image). j = 1 is the paper's two-frame speed matrix; larger j
// give slow objects (pedestrians) the longer baseline they need. Everything is planar float
// channels, ready to become a tensor; no learning here.
#pragma once

#include <deque>
#include <vector>

#include "dloam/core/range_image.hpp"
#include "dloam/core/sensor.hpp"
#include "dloam/core/types.hpp"

namespace dloam {

/// Channel layout: kBagRange, kBagX, kBagY, kBagZ, kBagIntensity, then speed image j at kBagSpeed + j - 1.
inline constexpr int kBagRange = 0, kBagX = 1, kBagY = 2, kBagZ = 3, kBagIntensity = 4, kBagSpeed = 5;
inline constexpr int bag_channels(int m) { return kBagSpeed + m; }

/// Value scaling of the channels (fixed, so training and inference agree).
inline constexpr float kBagMetricScale = 0.05f;   ///< range, x, y: metres * 0.05 (20 m -> 1)
inline constexpr float kBagHeightScale = 0.5f;    ///< z: metres * 0.5
inline constexpr float kBagSpeedClip = 3.0f;      ///< speeds above this many metres are clipped
inline constexpr float kBagSpeedUnknown = -1.0f;  ///< no previous scan / no return near the ray

struct RangeImageBag {
  int channels = 0, rows = 0, cols = 0;
  std::vector<float> data;  ///< channels * rows * cols, channel-major
  [[nodiscard]] float& at(int c, int px) { return data[static_cast<std::size_t>(c * rows * cols + px)]; }
  [[nodiscard]] float at(int c, int px) const { return data[static_cast<std::size_t>(c * rows * cols + px)]; }
};

/// A past scan as the bag needs it: its range channel (own frame, de-skewed) and world pose.
struct PastScan {
  std::vector<float> range;
  Pose pose = Pose::Identity();
};

/// The bag of the current scan: `image` projects `points` (de-skewed, current frame), `intensity`
/// is per point (empty: zeros), `pose` the current world pose (a prediction online); `past` holds
/// the most recent scans first. Speed image j is unknown (-1) everywhere when past has < j scans.
/// `speed1`: speed image 1 when the caller already has it (the geometric stage's speed matrix
/// against the previous scan with the same pose), else computed here.
RangeImageBag make_range_image_bag(const RangeImage& image, const std::vector<Vec3>& points,
                                   const std::vector<float>& intensity, const Pose& pose,
                                   const std::vector<const PastScan*>& past, int m,
                                   const SensorConfig& sensor, const std::vector<float>* speed1 = nullptr);

/// The m most recent scans, for the online pipeline.
class ScanHistory {
 public:
  ScanHistory(int m, const SensorConfig& sensor) : m_(m), sensor_(sensor) {}

  [[nodiscard]] RangeImageBag bag(const RangeImage& image, const std::vector<Vec3>& points,
                                  const std::vector<float>& intensity, const Pose& pose,
                                  const std::vector<float>* speed1 = nullptr) const;
  /// Adds a scan (its range channel, rows*cols, 0 = empty, and world pose) as the most recent one,
  /// dropping the oldest.
  void push(std::vector<float> range, const Pose& pose);
  /// Replaces the pose of the most recent scan (e.g. once the odometry refined it).
  void set_latest_pose(const Pose& pose);
  [[nodiscard]] std::size_t size() const { return frames_.size(); }
  [[nodiscard]] int m() const { return m_; }

 private:
  int m_;
  SensorConfig sensor_;
  std::deque<PastScan> frames_;  ///< front = most recent
};

}  // namespace dloam
