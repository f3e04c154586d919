// Sliding-minimum alignment of a sensor clock to the recording clock.
#include "dloam/drivers/stamp_alignment.hpp"

namespace dloam::drivers {

StampAlignment::StampAlignment(double window_s, double reset_s) : window_s_(window_s), reset_s_(reset_s) {}

double StampAlignment::update(double stamp, double sensor_time) {
  if (!(stamp > 0.0)) return offset();
  const double difference = stamp - sensor_time;
  if (!window_.empty() &&
      (sensor_time < last_sensor_time_ - reset_s_ || difference > window_.front().difference + reset_s_))
    window_.clear();
  last_sensor_time_ = sensor_time;
  while (!window_.empty() && window_.back().difference >= difference) window_.pop_back();
  window_.push_back({sensor_time, difference});
  while (window_.front().sensor_time < sensor_time - window_s_) window_.pop_front();
  return window_.front().difference;
}

}  // namespace dloam::drivers
