// Scan cutting per channel for spinning sensors whose channels look in different azimuths
// (azimuth offsets of several degrees): each channel leaves the scan where its own corrected
// azimuth (block azimuth + offset) crosses the cut angle, so no channel's ring is split across
// two scans. A scan is complete once the most lagging and the most leading channel (smallest and
// largest offset) have both crossed. Two buffers alternate: while the cut sweeps through the
// channels, the ones that have crossed fill the next scan.
//
// Angles are computed in float radians in the order of nebula's Hesai decoder, so that the
// channels change scans at the same firing as in nebula's reference clouds: corrected azimuth =
// float(block azimuth deg * pi / 180) + float(offset deg) * float(pi / 180), normalised to
// [0, 2 pi) with the float 2 pi; a channel crosses when cut is in [last, current) going forward.
#pragma once

#include <cstdint>
#include <vector>

namespace dloam::drivers {

class ChannelCut {
 public:
  /// `azimuth_offsets_deg`: each channel's offset; `cut_deg`: the cut azimuth, in the sensor's
  /// azimuth convention (clockwise, deg).
  ChannelCut(const std::vector<double>& azimuth_offsets_deg, double cut_deg);

  struct Step {
    int emitted = -1;      ///< buffer whose scan was completed by this firing (before it), -1: none
    bool crossed = false;  ///< some channel changed buffer at this firing
  };
  /// The next firing, at block azimuth `raw_azimuth` (0.01 deg, below 36000). The first firing
  /// (and the first after restart()) puts every channel in buffer 0, or, when it straddles the
  /// cut, the channels past the cut in buffer 1. `after_gap`: firings were lost before this one,
  /// so the rotor moved forward by whatever the azimuths say; otherwise an azimuth less than 10 deg
  /// behind the previous one is taken as jitter, not as a turn of almost 360 deg.
  Step step(std::uint16_t raw_azimuth, bool after_gap);
  /// Buffer (0 or 1) that `channel`'s returns of the last firing go to.
  [[nodiscard]] std::uint8_t buffer(int channel) const { return buffer_[static_cast<std::size_t>(channel)]; }
  /// The buffer that the next completed scan is in.
  [[nodiscard]] int pending() const { return pending_; }
  /// The last firing's channels are in both buffers.
  [[nodiscard]] bool split() const { return buffer_[lag_] != buffer_[lead_]; }
  /// No firing yet (or restarted).
  [[nodiscard]] bool fresh() const { return fresh_; }
  /// The next firing starts over as the first one, with buffer 0 pending.
  void restart() { fresh_ = true; }
  /// Corrected azimuth (float rad in [0, 2 pi)) of `channel` at block azimuth `raw_azimuth`.
  [[nodiscard]] float corrected_azimuth(std::uint16_t raw_azimuth, int channel) const;

 private:
  void initialise();
  [[nodiscard]] bool far_from_cut(std::uint16_t raw_azimuth) const;
  std::vector<float> offset_rad_;
  std::vector<float> current_, last_;
  std::vector<std::uint8_t> buffer_;
  std::size_t lag_ = 0, lead_ = 0;  ///< channels with the smallest / largest offset
  float cut_ = 0.0f;
  double cut_deg_ = 0.0, min_offset_deg_ = 0.0, spread_deg_ = 0.0;
  int pending_ = 0;
  bool fresh_ = true;
  // Firings far from the cut are skipped (nothing can cross there); last_ is then stale and is
  // recomputed from last_raw_.
  std::uint16_t last_raw_ = 0;
  bool last_far_ = false, stale_ = false;
};

}  // namespace dloam::drivers
