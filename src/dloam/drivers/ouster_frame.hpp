// Assembly of Ouster lidar packets into frames: one frame per frame_id, each column stored at
// its measurement_id (the staggered layout of ouster-sdk's LidarScan), with the column window of
// the metadata deciding which measurement ids a complete frame has.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dloam/drivers/ouster_metadata.hpp"
#include "dloam/drivers/ouster_profiles.hpp"

namespace dloam::drivers {

/// One frame as the packets gave it, indexed by measurement_id (0..W-1). Columns that did not
/// arrive, or arrived with the valid bit clear, are zero (headers and pixels), as in ouster-sdk.
struct OusterFrame {
  std::uint32_t frame_id = 0;
  int width = 0, height = 0;
  std::size_t column_size = 0;           ///< bytes of a stored column (the packet's layout)
  std::vector<std::uint64_t> timestamp;  ///< per column, ns of the sensor clock
  std::vector<std::uint16_t> measurement_id;
  std::vector<std::uint32_t> status;
  std::vector<std::uint8_t> valid;    ///< 1: a valid column is stored here
  std::vector<std::uint8_t> columns;  ///< width * column_size bytes
  int valid_columns = 0;
  std::size_t first_packet = 0, last_packet = 0;  ///< packet indices
  int packets = 0;
  /// Every measurement id of the column window arrived with its valid bit set.
  bool complete = false;

  [[nodiscard]] const std::uint8_t* column(int m) const {
    return columns.data() + static_cast<std::size_t>(m) * column_size;
  }
  /// A channel field as an H x W row-major image (row = pixel, column = measurement_id), the
  /// values after mask and upshift. Throws std::invalid_argument when the profile has no such field.
  [[nodiscard]] std::vector<std::uint32_t> field(const OusterPacketFormat& format, OusterField f) const;
};

/// Destaggers an H x W row-major image: pixel (row, m) moves to column (m + shift[row]) mod W.
template <typename T>
std::vector<T> ouster_destagger(const std::vector<T>& image, int width, const std::vector<int>& shift) {
  std::vector<T> out(image.size());
  const int h = static_cast<int>(shift.size());
  for (int r = 0; r < h; ++r) {
    const int s = ((shift[static_cast<std::size_t>(r)] % width) + width) % width;
    for (int m = 0; m < width; ++m)
      out[static_cast<std::size_t>(r * width + (m + s) % width)] =
          image[static_cast<std::size_t>(r * width + m)];
  }
  return out;
}

class OusterFrameBatcher {
 public:
  OusterFrameBatcher(const OusterMetadata& metadata, const OusterPacketFormat& format);

  /// Adds one lidar packet (format.packet_size bytes); frames it finishes are appended to `done`.
  /// A frame finishes when every measurement id of the column window has arrived, or when a
  /// packet of another frame_id comes. Packets of the frame finished last (stragglers) are
  /// dropped and counted. Throws InputError naming `where` and the metadata file when a
  /// measurement_id does not fit the metadata's columns_per_frame.
  void add(const std::uint8_t* packet, std::size_t index, const std::string& where,
           std::vector<OusterFrame>& done);
  /// The frame being assembled, if any (partial).
  void finish(std::vector<OusterFrame>& done);
  /// Hands a consumed frame back so that its buffers are reused.
  void recycle(OusterFrame&& frame);

  [[nodiscard]] std::size_t late_packets() const { return late_packets_; }
  [[nodiscard]] std::size_t invalid_columns() const { return invalid_columns_; }

 private:
  void start(std::uint32_t frame_id, std::size_t index);
  void close(std::vector<OusterFrame>& done);

  const OusterPacketFormat& format_;
  std::string source_;
  int width_, height_, window_columns_;
  std::vector<std::uint8_t> in_window_;
  OusterFrame current_;
  bool active_ = false;
  std::vector<std::uint8_t> arrived_;
  int arrived_in_window_ = 0;
  bool have_finished_ = false;
  std::uint32_t last_finished_ = 0;
  std::vector<OusterFrame> pool_;
  std::size_t late_packets_ = 0, invalid_columns_ = 0;
};

}  // namespace dloam::drivers
