#include "dloam/drivers/ouster_frame.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "dloam/core/types.hpp"

namespace dloam::drivers {

std::vector<std::uint32_t> OusterFrame::field(const OusterPacketFormat& format, OusterField f) const {
  const OusterFieldLayout* layout = format.field(f);
  if (!layout) throw std::invalid_argument(std::string("ouster: the profile has no field ") + to_string(f));
  std::vector<std::uint32_t> image(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0);
  for (int m = 0; m < width; ++m) {
    if (!valid[static_cast<std::size_t>(m)]) continue;
    const std::uint8_t* col = column(m);
    for (int px = 0; px < height; ++px)
      image[static_cast<std::size_t>(px) * static_cast<std::size_t>(width) + static_cast<std::size_t>(m)] =
          layout->decode(format.pixel(col, px));
  }
  return image;
}

OusterFrameBatcher::OusterFrameBatcher(const OusterMetadata& md, const OusterPacketFormat& format)
    : format_(format),
      source_(md.source),
      width_(md.columns_per_frame),
      height_(md.pixels_per_column),
      window_columns_(md.window_columns()),
      in_window_(static_cast<std::size_t>(md.columns_per_frame), 0),
      arrived_(static_cast<std::size_t>(md.columns_per_frame), 0) {
  for (int m = 0; m < width_; ++m) in_window_[static_cast<std::size_t>(m)] = md.in_window(m) ? 1 : 0;
}

void OusterFrameBatcher::recycle(OusterFrame&& frame) {
  if (pool_.size() < 4) pool_.push_back(std::move(frame));
}

void OusterFrameBatcher::start(std::uint32_t frame_id, std::size_t index) {
  if (!pool_.empty()) {
    current_ = std::move(pool_.back());
    pool_.pop_back();
  } else {
    current_ = OusterFrame{};
  }
  const auto w = static_cast<std::size_t>(width_);
  current_.frame_id = frame_id;
  current_.width = width_;
  current_.height = height_;
  current_.column_size = format_.column_size;
  current_.timestamp.assign(w, 0);
  current_.measurement_id.assign(w, 0);
  current_.status.assign(w, 0);
  current_.valid.assign(w, 0);
  current_.columns.resize(w * format_.column_size);
  current_.valid_columns = 0;
  current_.first_packet = current_.last_packet = index;
  current_.packets = 0;
  current_.complete = false;
  std::fill(arrived_.begin(), arrived_.end(), 0);
  arrived_in_window_ = 0;
  active_ = true;
}

void OusterFrameBatcher::close(std::vector<OusterFrame>& done) {
  // Zero the columns that hold no valid data (a reused buffer keeps an older frame's bytes).
  for (int m = 0; m < width_; ++m)
    if (!current_.valid[static_cast<std::size_t>(m)])
      std::memset(current_.columns.data() + static_cast<std::size_t>(m) * format_.column_size, 0,
                  format_.column_size);
  int valid_in_window = 0;
  for (int m = 0; m < width_; ++m)
    if (current_.valid[static_cast<std::size_t>(m)] && in_window_[static_cast<std::size_t>(m)])
      ++valid_in_window;
  current_.complete = valid_in_window == window_columns_;
  have_finished_ = true;
  last_finished_ = current_.frame_id;
  active_ = false;
  done.push_back(std::move(current_));
  current_ = OusterFrame{};
}

void OusterFrameBatcher::add(const std::uint8_t* packet, std::size_t index, const std::string& where,
                             std::vector<OusterFrame>& done) {
  const std::uint32_t frame_id = format_.frame_id(packet);
  if (active_ && frame_id != current_.frame_id) close(done);
  if (!active_) {
    if (have_finished_ && frame_id == last_finished_) {
      ++late_packets_;
      return;
    }
    start(frame_id, index);
  }
  ++current_.packets;
  current_.last_packet = index;
  for (int c = 0; c < format_.columns_per_packet; ++c) {
    const std::uint8_t* col = format_.column(packet, c);
    const std::uint16_t m = format_.col_measurement_id(col);
    if (m >= width_)
      throw InputError(where + ": measurement_id " + std::to_string(m) + " in column " + std::to_string(c) +
                       " does not fit the " + std::to_string(width_) + " columns per frame of " + source_ +
                       " (is it this sensor's metadata?)");
    const auto mi = static_cast<std::size_t>(m);
    if (!arrived_[mi]) {
      arrived_[mi] = 1;
      if (in_window_[mi]) ++arrived_in_window_;
    }
    const std::uint32_t status = format_.col_status(col);
    if (!(status & 1u)) {
      ++invalid_columns_;
      continue;
    }
    if (!current_.valid[mi]) ++current_.valid_columns;
    current_.valid[mi] = 1;
    current_.timestamp[mi] = format_.col_timestamp(col);
    current_.measurement_id[mi] = m;
    current_.status[mi] = status;
    std::memcpy(current_.columns.data() + mi * format_.column_size, col, format_.column_size);
  }
  if (arrived_in_window_ == window_columns_) close(done);
}

void OusterFrameBatcher::finish(std::vector<OusterFrame>& done) {
  if (active_) close(done);
}

}  // namespace dloam::drivers
