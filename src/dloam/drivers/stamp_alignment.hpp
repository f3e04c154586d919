// Times a sensor's packets on the recording clock when the sensor's own clock is not synchronised
// with it: the sensor clock gives the spacing of the packets (it is steady), the recording stamps
// (receive times, delayed by a varying latency and bunched after a stall) give the time base.
#pragma once

#include <deque>

namespace dloam::drivers {

/// Offset from a sensor clock to the recording clock: the smallest (stamp - sensor time) over the
/// last `window_s` of sensor time, i.e. the least-delayed recent packet. Starts over when a
/// packet's difference exceeds that minimum, or its sensor time falls behind the previous one, by
/// more than `reset_s` (a clock jump). Causal: the offset of a packet depends on it and the packets
/// before it only.
class StampAlignment {
 public:
  explicit StampAlignment(double window_s = 1.0, double reset_s = 1.0);
  /// Adds a packet recorded at `stamp` (s; <= 0: no recording time) whose sensor time is
  /// `sensor_time` (s) and returns the offset for it: recording time = sensor_time + offset. Without
  /// recording times the offset stays 0 (sensor times are used as they are).
  double update(double stamp, double sensor_time);
  [[nodiscard]] double offset() const { return window_.empty() ? 0.0 : window_.front().difference; }

 private:
  struct Sample {
    double sensor_time;
    double difference;  ///< stamp - sensor_time
  };
  double window_s_, reset_s_;
  double last_sensor_time_ = 0.0;
  std::deque<Sample> window_;  ///< differences increasing from front to back (sliding minimum)
};

}  // namespace dloam::drivers
