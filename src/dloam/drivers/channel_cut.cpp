// Per-channel scan cut with two alternating buffers.
#include "dloam/drivers/channel_cut.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dloam::drivers {

namespace {

const float kTwoPiF = 2.0f * static_cast<float>(M_PI);
const float kBackwardTolerance = static_cast<float>(10.0 * M_PI / 180.0);

// angle - floor(angle / 2 pi) x 2 pi in double, for angles within one turn of [0, 2 pi) (block
// azimuth + offset always are) without the division.
float normalise(float angle) {
  const double a = angle, m = kTwoPiF;
  if (a < 0.0) return static_cast<float>(a < -m ? a - std::floor(a / m) * m : a + m);
  if (a >= m) return static_cast<float>(a >= 2.0 * m ? a - std::floor(a / m) * m : a - m);
  return angle;
}

// True when `angle` lies in the sector from `start` clockwise to `end` (all in [0, 2 pi)).
bool in_sector(float start, float end, float angle, bool start_inclusive, bool end_inclusive) {
  if (start == end) return angle != start || start_inclusive || end_inclusive;
  if (!start_inclusive && angle == start) return false;
  if (!end_inclusive && angle == end) return false;
  if (end < start) return angle <= end || start <= angle;
  return start <= angle && angle <= end;
}

}  // namespace

ChannelCut::ChannelCut(const std::vector<double>& azimuth_offsets_deg, double cut_deg) {
  if (azimuth_offsets_deg.empty()) throw std::invalid_argument("ChannelCut: no channels");
  const float deg_to_rad = static_cast<float>(M_PI / 180.0);
  for (const double a : azimuth_offsets_deg) offset_rad_.push_back(static_cast<float>(a) * deg_to_rad);
  current_.assign(offset_rad_.size(), 0.0f);
  last_ = current_;
  buffer_.assign(offset_rad_.size(), 0);
  lag_ = static_cast<std::size_t>(std::min_element(offset_rad_.begin(), offset_rad_.end()) -
                                  offset_rad_.begin());
  lead_ = static_cast<std::size_t>(std::max_element(offset_rad_.begin(), offset_rad_.end()) -
                                   offset_rad_.begin());
  cut_ = normalise(static_cast<float>(cut_deg * (M_PI / 180.0)));
  const auto [lo, hi] = std::minmax_element(azimuth_offsets_deg.begin(), azimuth_offsets_deg.end());
  min_offset_deg_ = *lo;
  spread_deg_ = *hi - *lo;
  cut_deg_ = std::fmod(std::fmod(cut_deg, 360.0) + 360.0, 360.0);
}

float ChannelCut::corrected_azimuth(std::uint16_t raw_azimuth, int channel) const {
  const auto block = static_cast<float>((raw_azimuth / 100.0) * (M_PI / 180.0));
  return normalise(block + offset_rad_[static_cast<std::size_t>(channel)]);
}

void ChannelCut::initialise() {
  const float region_start = normalise(cut_ - kTwoPiF / 4);
  const float region_end = normalise(cut_ + kTwoPiF / 4);
  const float half_end = normalise(cut_ + kTwoPiF / 2);
  const float lag = current_[lag_], lead = current_[lead_];
  const bool near_cut = in_sector(region_start, region_end, lag, true, true) &&
                        in_sector(region_start, region_end, lead, true, true);
  const int beyond = static_cast<int>(in_sector(cut_, half_end, lag, false, true)) +
                     static_cast<int>(in_sector(cut_, half_end, lead, false, true));
  const bool straddles = near_cut && beyond == 1;
  for (std::size_t c = 0; c < current_.size(); ++c)
    buffer_[c] = straddles && in_sector(cut_, half_end, current_[c], false, true) ? 1 : 0;
  last_ = current_;
  pending_ = 0;
  fresh_ = false;
}

bool ChannelCut::far_from_cut(std::uint16_t raw_azimuth) const {
  // Where the firing's corrected azimuths [block + min offset, block + max offset] lie relative to
  // the cut, in deg; far when the cut is more than kFarDeg outside that sector.
  constexpr double kFarDeg = 20.0;
  const double from_cut = std::fmod(raw_azimuth / 100.0 + min_offset_deg_ - cut_deg_ + 720.0, 360.0);
  return from_cut >= kFarDeg && from_cut <= 360.0 - spread_deg_ - kFarDeg;
}

ChannelCut::Step ChannelCut::step(std::uint16_t raw_azimuth, bool after_gap) {
  Step step;
  const bool far = far_from_cut(raw_azimuth);
  const int moved = (raw_azimuth - last_raw_ + 36000) % 36000;
  if (!fresh_ && !after_gap && far && last_far_ && (moved < 1000 || moved > 35000)) {
    // Away from the cut and a small step (forward or jitter back): no channel can cross, and the
    // channels' azimuths are computed again from last_raw_ when the cut comes near.
    last_raw_ = raw_azimuth;
    stale_ = true;
    return step;
  }
  const auto block = static_cast<float>((raw_azimuth / 100.0) * (M_PI / 180.0));
  const std::size_t n = offset_rad_.size();
  for (std::size_t c = 0; c < n; ++c) current_[c] = normalise(block + offset_rad_[c]);
  if (fresh_) {
    initialise();
    last_raw_ = raw_azimuth;
    last_far_ = far;
    stale_ = false;
    return step;
  }
  if (stale_) {
    for (std::size_t c = 0; c < n; ++c) last_[c] = corrected_azimuth(last_raw_, static_cast<int>(c));
    stale_ = false;
  }
  for (std::size_t c = 0; c < n; ++c) {
    const float last = last_[c], now = current_[c];
    if (now == last) continue;
    if (now < last) {
      // Behind the previous azimuth: the wrap through 0, or (a small step back) jitter, which
      // keeps the furthest azimuth so that the channel cannot cross the cut twice.
      if (!after_gap && last - now < kBackwardTolerance) continue;
      if (now != cut_ && (cut_ <= now || last <= cut_)) {
        buffer_[c] ^= 1;
        step.crossed = true;
      }
    } else if (now != cut_ && last <= cut_ && cut_ <= now) {
      buffer_[c] ^= 1;
      step.crossed = true;
    }
    last_[c] = now;
  }
  last_raw_ = raw_azimuth;
  last_far_ = far;
  if (buffer_[lag_] != pending_ && buffer_[lead_] != pending_) {
    step.emitted = pending_;
    pending_ ^= 1;
  }
  return step;
}

}  // namespace dloam::drivers
