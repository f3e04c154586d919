#include "dloam/drivers/ouster.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numeric>
#include <sstream>

#include "dloam/core/enum_names.hpp"
#include "dloam/core/types.hpp"

namespace dloam::drivers {

namespace {

constexpr int kColumnsPerPacket = 16;
constexpr OusterProfile kProfiles[] = {
    OusterProfile::kLegacy,      OusterProfile::kSingle,          OusterProfile::kDual,
    OusterProfile::kLowDataRate, OusterProfile::kLowDataRateDual, OusterProfile::kFusaLowDataRateDual};
constexpr int kPixelCounts[] = {8, 16, 32, 64, 128};

OusterMetadata probe_metadata(OusterProfile profile, int pixels) {
  OusterMetadata md;
  md.profile = profile;
  md.fusa_header = profile == OusterProfile::kFusaLowDataRateDual;
  md.pixels_per_column = pixels;
  md.columns_per_packet = kColumnsPerPacket;
  return md;
}

/// Structure of a packet against one layout: packet type 1, consecutive measurement ids of a
/// frame position (valid columns), a LEGACY column status of all ones or zero.
bool fits_layout(const Packet& p, const OusterPacketFormat& f) {
  if (p.size != f.packet_size) return false;
  if (!f.legacy && f.packet_type(p.data) != 1) return false;
  int first = -1, valid = 0;
  for (int c = 0; c < f.columns_per_packet; ++c) {
    const std::uint8_t* col = f.column(p.data, c);
    const std::uint32_t status = f.col_status(col);
    if (f.legacy && status != 0xFFFFFFFFu && status != 0u) return false;
    if (!(status & 1u)) continue;
    const int m = f.col_measurement_id(col);
    if (first < 0) first = m - c;
    if (m != first + c || m >= 4096) return false;
    ++valid;
  }
  return valid > 0 && first >= 0 && first % f.columns_per_packet == 0;
}

/// "LEGACY with 32 pixels" for the layouts a packet size would fit (16 columns per packet).
std::string layouts_of_size(std::size_t size) {
  std::string out;
  for (const OusterProfile p : kProfiles) {
    if (p == OusterProfile::kFusaLowDataRateDual) continue;  // same sizes as RNG15_RFL8_NIR8_DUAL
    for (const int h : kPixelCounts) {
      if (OusterPacketFormat(probe_metadata(p, h)).packet_size != size) continue;
      out +=
          (out.empty() ? "" : " or ") + std::string(to_string(p)) + " with " + std::to_string(h) + " pixels";
    }
  }
  return out;
}

/// The packet's index: the last number in `where` ("drive.pcap: packet 1207"), else `fallback`.
std::size_t packet_index(const Packet& p, std::size_t fallback) {
  const std::string& w = p.where;
  std::size_t end = w.size();
  while (end > 0 && !std::isdigit(static_cast<unsigned char>(w[end - 1]))) --end;
  std::size_t begin = end;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(w[begin - 1]))) --begin;
  if (begin == end || end - begin > 18) return fallback;
  return static_cast<std::size_t>(std::stoull(w.substr(begin, end - begin)));
}

std::string where_of(const Packet& p, std::size_t index) {
  return p.where.empty() ? "packet " + std::to_string(index) : p.where;
}

std::string normalized_model(const std::string& s) {
  std::string out;
  for (const char c : s)
    if (std::isalnum(static_cast<unsigned char>(c)))
      out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

void ouster_range_limits(const std::string& prod_line, double& min_range, double& max_range) {
  min_range = 0.5;  // firmware 3's default min_range_threshold_cm (50)
  if (prod_line.rfind("OS-0", 0) == 0 || prod_line.rfind("OS0", 0) == 0) {
    max_range = 100.0;
  } else if (prod_line.rfind("OS-2", 0) == 0 || prod_line.rfind("OS2", 0) == 0) {
    max_range = 400.0;
  } else {
    max_range = 200.0;  // OS-1 and unknown lines
  }
}

bool looks_like_ouster(const Packet& packet) {
  if (!packet.data || packet.size < 64) return false;
  for (const OusterProfile p : kProfiles)
    for (const int h : kPixelCounts)
      if (fits_layout(packet, OusterPacketFormat(probe_metadata(p, h)))) return true;
  return false;
}

OusterScanner::OusterScanner(OusterMetadata metadata, const DriverOptions& options,
                             std::shared_ptr<const OusterXyzLut> lut)
    : md_(std::move(metadata)),
      options_(options),
      format_(md_),
      lut_(lut ? std::move(lut) : std::make_shared<const OusterXyzLut>(md_)),
      batcher_(md_, format_) {
  if (!options_.model.empty() && !md_.prod_line.empty()) {
    const std::string a = normalized_model(options_.model), b = normalized_model(md_.prod_line);
    if (b.rfind(a, 0) != 0 && a.rfind(b, 0) != 0)
      throw InputError(md_.source + ": the metadata is for a " + md_.prod_line +
                       ", not the requested model " + options_.model);
  }
  preset_ = !md_.prod_line.empty() ? md_.prod_line : (!options_.model.empty() ? options_.model : "Ouster");
  const int h = md_.pixels_per_column;
  std::vector<int> order(static_cast<std::size_t>(h));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return md_.beam_altitude_deg[static_cast<std::size_t>(a)] <
           md_.beam_altitude_deg[static_cast<std::size_t>(b)];
  });
  ring_of_row_.resize(static_cast<std::size_t>(h));
  for (int k = 0; k < h; ++k)
    ring_of_row_[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] =
        static_cast<std::uint16_t>(k);

  double lo = 0.0, hi = 0.0;
  ouster_range_limits(preset_, lo, hi);
  if (md_.min_range_threshold_m > lo) lo = md_.min_range_threshold_m;
  if (options_.scan.min_range > 0.0) lo = options_.scan.min_range;
  if (options_.scan.max_range > 0.0) hi = options_.scan.max_range;
  if (!(hi > lo))
    throw InputError(md_.source + ": the range limits " + std::to_string(lo) + " - " + std::to_string(hi) +
                     " m leave no points");
  min_mm_ = lo * 1000.0;
  max_mm_ = hi * 1000.0;
  crc_mode_ = !format_.may_have_crc() ? 0 : (md_.crc_expected() == 0 ? 0 : -1);
}

bool OusterScanner::check(const Packet& p) const { return check(p, packets_seen_); }

bool OusterScanner::check(const Packet& p, std::size_t fallback_index) const {
  const std::size_t index = packet_index(p, fallback_index);
  const std::string where = where_of(p, index);
  const bool on_imu_port = p.port != 0 && md_.udp_port_imu != 0 && p.port == md_.udp_port_imu &&
                           md_.udp_port_imu != md_.udp_port_lidar;
  if (p.size == format_.packet_size && !on_imu_port) {
    if (!p.data) throw InputError(where + ": empty packet");
    if (!format_.legacy) {
      const std::uint16_t type = format_.packet_type(p.data);
      if (type != 1)
        throw InputError(where + ": packet type " + std::to_string(type) +
                         " is not a lidar packet (1) of the " + to_string(format_.profile) + " layout of " +
                         md_.source);
      const std::uint64_t sn = format_.prod_sn(p.data);
      if (md_.prod_sn != 0 && sn != 0 && sn != md_.prod_sn)
        throw InputError(where + ": the packet comes from sensor " + std::to_string(sn) + " but " +
                         md_.source + " is the metadata of sensor " + std::to_string(md_.prod_sn));
      const std::uint32_t init = format_.init_id(p.data);
      if (md_.init_id != 0 && init != 0 && init != md_.init_id)
        throw InputError(where + ": initialization id " + std::to_string(init) + " differs from " +
                         md_.source + "'s " + std::to_string(md_.init_id) +
                         " (the sensor was reconfigured or restarted: its metadata must be saved again)");
    }
    return true;
  }
  if ((md_.imu_packet_size > 0 && p.size == static_cast<std::size_t>(md_.imu_packet_size)) || on_imu_port)
    return false;
  if (md_.imu_packet_size == 0 && p.size > 164 && (p.size - 164) % 36 == 0 && p.size <= 164 + 36 * 1000)
    return false;
  std::string msg = where + ": a " + std::to_string(p.size) + "-byte packet does not fit " + md_.source +
                    ": " + to_string(format_.profile) + " with " + std::to_string(format_.pixels_per_column) +
                    " pixels and " + std::to_string(format_.columns_per_packet) +
                    " columns per packet makes " + std::to_string(format_.packet_size) +
                    "-byte lidar packets";
  if (md_.imu_packet_size > 0) msg += " (IMU: " + std::to_string(md_.imu_packet_size) + " B)";
  const std::string alt = layouts_of_size(p.size);
  if (!alt.empty())
    msg += "; " + std::to_string(p.size) + " B would be " + alt + " (is it this sensor's metadata?)";
  throw InputError(msg);
}

void OusterScanner::update_clock(const Packet& p, std::uint64_t sensor_ns) {
  if (!(p.stamp > 0.0) || sensor_ns == 0) return;
  const double sensor = static_cast<double>(sensor_ns) * 1e-9;
  if (clock_set_ && std::abs(sensor + clock_offset_ - p.stamp) <= 1.0) return;
  if (clock_set_) ++stats_.clock_reanchors;
  clock_offset_ = std::abs(p.stamp - sensor) < 10.0 ? 0.0 : p.stamp - sensor;
  clock_set_ = true;
}

void OusterScanner::add(const Packet& p, std::vector<Scan>& done) {
  const std::size_t index = packet_index(p, packets_seen_);
  const bool lidar = check(p);
  ++packets_seen_;
  if (!lidar) {
    ++stats_.imu_packets;
    return;
  }
  if (crc_mode_ != 0) {
    const bool ok = OusterPacketFormat::compute_crc(p.data, p.size) == format_.stored_crc(p.data, p.size);
    if (crc_mode_ < 0 && ok) crc_mode_ = 1;  // the stream carries CRCs from here on
    if (crc_mode_ > 0) {
      ++stats_.crc_checked;
      if (!ok) {
        ++stats_.crc_bad;
        return;
      }
    }
  }
  ++stats_.lidar_packets;
  for (int c = format_.columns_per_packet - 1; c >= 0; --c) {
    const std::uint8_t* col = format_.column(p.data, c);
    if (format_.col_status(col) & 1u) {
      update_clock(p, format_.col_timestamp(col));
      break;
    }
  }
  std::vector<OusterFrame> frames;
  batcher_.add(p.data, index, where_of(p, index), frames);
  for (auto& f : frames) convert(f, done);
}

void OusterScanner::finish(std::vector<Scan>& done) {
  std::vector<OusterFrame> frames;
  batcher_.finish(frames);
  for (auto& f : frames)
    if (f.valid_columns > 0) convert(f, done);
}

bool OusterScanner::outline_only(bool on) {
  outline_ = on;
  return true;
}

std::unique_ptr<Scanner> OusterScanner::restart() const {
  return std::make_unique<OusterScanner>(md_, options_, lut_);
}

void OusterScanner::convert(OusterFrame& frame, std::vector<Scan>& done) {
  if (outline_) {
    convert<false>(frame, done);
  } else {
    convert<true>(frame, done);
  }
}

template <bool kPoints>
void OusterScanner::convert(OusterFrame& frame, std::vector<Scan>& done) {
  Scan s;
  const int h = frame.height, w = frame.width;
  const bool dual = format_.dual();
  const ReturnMode mode = options_.scan.returns;
  const std::size_t capacity = static_cast<std::size_t>(frame.valid_columns) * static_cast<std::size_t>(h) *
                               (dual && mode == ReturnMode::kAll ? 2 : 1);
  // Sized once and cut back at the end: the per-point loop writes through plain pointers.
  if constexpr (kPoints) s.resize_points(capacity);
  Vec3* out_xyz = s.xyz.data();
  float* out_intensity = s.intensity.data();
  std::uint16_t* out_ring = s.ring.data();
  std::uint8_t* out_rid = s.return_id.data();
  double* out_t = s.stamps.data();
  std::size_t n = 0;

  const OusterFieldLayout& range = *format_.field(OusterField::kRange);
  const OusterFieldLayout& refl = *format_.field(OusterField::kReflectivity);
  const OusterFieldLayout* range2 = format_.field(OusterField::kRange2);
  const OusterFieldLayout* refl2 = format_.field(OusterField::kReflectivity2);
  // Which return is the strongest when the sensor does not put it first.
  const OusterFieldLayout* strength = format_.field(OusterField::kSignal);
  const OusterFieldLayout* strength2 = format_.field(OusterField::kSignal2);
  if (!strength || !strength2) {
    strength = &refl;
    strength2 = refl2;
  }
  const bool strongest_first = md_.return_order == OusterReturnOrder::kStrongestToWeakest;
  const auto lo = static_cast<std::uint32_t>(std::ceil(min_mm_));
  const auto hi = max_mm_ >= 4.0e9 ? 0xFFFFFFFFu : static_cast<std::uint32_t>(std::floor(max_mm_));
  const std::uint16_t* ring_of_row = ring_of_row_.data();
  const OusterXyzLut& lut = *lut_;

  bool first_time = true;
  for (int m = 0; m < w; ++m) {
    if (!frame.valid[static_cast<std::size_t>(m)]) continue;
    const double t = static_cast<double>(frame.timestamp[static_cast<std::size_t>(m)]) * 1e-9 + clock_offset_;
    if (first_time) s.start = t;
    first_time = false;
    s.end = t;
    const std::uint8_t* col = frame.column(m);
    auto emit = [&](int row, std::uint32_t r, std::uint32_t intensity, std::uint8_t rid) {
      if (r < lo || r > hi) return;
      if constexpr (kPoints) {
        out_xyz[n] = lut.point(row, m, static_cast<double>(r));
        out_intensity[n] = static_cast<float>(intensity);
        out_ring[n] = ring_of_row[row];
        out_rid[n] = rid;
        out_t[n] = t;
      }
      ++n;
    };
    if (!dual) {
      for (int row = 0; row < h; ++row) {
        const std::uint8_t* px = format_.pixel(col, row);
        const std::uint32_t r = range.decode(px);
        if (r != 0) emit(row, r, refl.decode(px), 0);
      }
      continue;
    }
    for (int row = 0; row < h; ++row) {
      const std::uint8_t* px = format_.pixel(col, row);
      const std::uint32_t r0 = range.decode(px);
      const std::uint32_t r1 = range2->decode(px);
      if (r0 == 0 && r1 == 0) continue;
      const std::uint32_t near = r0 == 0 ? r1 : (r1 == 0 ? r0 : std::min(r0, r1));
      const std::uint32_t far = r0 != 0 && r1 != 0 ? std::max(r0, r1) : 0;  // 0: one return only
      auto slot_of = [&](std::uint32_t r) { return r == r0 ? 0 : 1; };
      auto put = [&](int slot) {
        const std::uint32_t r = slot == 0 ? r0 : r1;
        const std::uint8_t rid = far != 0 && far != near && r == far ? 1 : 0;
        emit(row, r, slot == 0 ? refl.decode(px) : refl2->decode(px), rid);
      };
      switch (mode) {
        case ReturnMode::kFirst:
          put(slot_of(near));
          break;
        case ReturnMode::kLast:
          put(slot_of(far != 0 ? far : near));
          break;
        case ReturnMode::kStrongest: {
          int slot = r0 != 0 ? 0 : 1;
          if (r0 != 0 && r1 != 0 && !strongest_first)
            slot = strength->decode(px) >= strength2->decode(px) ? 0 : 1;
          put(slot);
          break;
        }
        case ReturnMode::kAll:
          put(slot_of(near));
          if (far != 0 && far != near) put(slot_of(far));
          break;
      }
    }
  }
  if constexpr (kPoints) {
    s.resize_points(n);
  } else {
    s.outline_points = n;
  }
  s.first_packet = frame.first_packet;
  s.last_packet = frame.last_packet;
  s.complete = frame.complete;
  ++stats_.frames;
  if (frame.complete) ++stats_.complete_frames;
  if (keep_frames_) {
    kept_.push_back(std::move(frame));
  } else {
    batcher_.recycle(std::move(frame));
  }
  done.push_back(std::move(s));
}

OusterStats OusterScanner::stats() const {
  OusterStats s = stats_;
  s.late_packets = batcher_.late_packets();
  s.invalid_columns = batcher_.invalid_columns();
  return s;
}

SensorConfig OusterScanner::sensor() const {
  SensorConfig s;
  s.preset = preset_;
  s.N_scan = md_.pixels_per_column;
  s.Horizon_SCAN = md_.columns_per_frame;
  const auto h = static_cast<std::size_t>(md_.pixels_per_column);
  std::vector<double> el(h), dz(h);
  for (std::size_t row = 0; row < h; ++row) {
    el[ring_of_row_[row]] = md_.beam_altitude_deg[row];
    dz[ring_of_row_[row]] = lut_->row_origin_heights()[row];
  }
  // Two beams at one elevation (not in any file seen) would break the strictly increasing table.
  for (std::size_t k = 1; k < el.size(); ++k)
    if (el[k] <= el[k - 1]) el[k] = el[k - 1] + 1e-6;
  s.beam_elevations_deg = el;
  s.beam_vertical_offsets_m = dz;
  s.Pit_bottom = el.front();
  s.fov_top = el.back();
  s.min_range = min_mm_ / 1000.0;
  s.max_range = max_mm_ / 1000.0;
  s.scan_rate_hz = md_.fps;
  s.vertical_angle_correction_deg = 0.0;
  return s;
}

std::string OusterScanner::describe() const {
  const OusterStats st = stats();
  std::ostringstream o;
  o << "Ouster " << preset_;
  if (!md_.firmware.empty() || md_.prod_sn != 0) {
    o << " (";
    if (!md_.firmware.empty()) o << "fw " << md_.firmware << (md_.prod_sn != 0 ? ", " : "");
    if (md_.prod_sn != 0) o << "sn " << md_.prod_sn;
    o << ")";
  }
  o << ", " << to_string(md_.profile) << ", " << md_.columns_per_frame << "x" << md_.fps << ", "
    << md_.pixels_per_column
    << " beams, returns: " << (format_.dual() ? std::string(name_of(options_.scan.returns)) : "single")
    << "; " << st.lidar_packets << " lidar packets, " << st.frames << " frames (" << st.complete_frames
    << " complete), " << st.imu_packets << " IMU packets ignored";
  if (st.late_packets) o << ", " << st.late_packets << " late packets dropped";
  if (st.invalid_columns) o << ", " << st.invalid_columns << " invalid columns";
  if (crc_mode_ > 0) {
    o << ", CRC: " << st.crc_checked - st.crc_bad << " good, " << st.crc_bad << " bad (dropped)";
  } else if (crc_mode_ < 0) {
    o << ", CRC: none found";
  }
  o << "; times: "
    << (clock_set_ ? (clock_offset_ == 0.0 ? "sensor clock" : "sensor clock + recording offset")
                   : "sensor clock");
  if (st.clock_reanchors) o << " (re-anchored " << st.clock_reanchors << " times)";
  return o.str();
}

std::unique_ptr<Scanner> make_ouster_scanner(const DriverOptions& options,
                                             const std::vector<Packet>& first_packets) {
  if (options.calibration.empty())
    throw InputError(
        "Ouster packets cannot be decoded without the sensor's metadata JSON (beam angles, lidar mode, "
        "packet "
        "profile): give it as the calibration file (ouster-sdk saves it beside a recording; a sensor serves "
        "it "
        "at http://<sensor>/api/v1/sensor/metadata)");
  auto scanner = std::make_unique<OusterScanner>(load_ouster_metadata(options.calibration), options);
  for (std::size_t i = 0; i < first_packets.size(); ++i) scanner->check(first_packets[i], i);
  return scanner;
}

}  // namespace dloam::drivers
