#include "dloam/drivers/velodyne.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <type_traits>

#include "dloam/core/types.hpp"
#include "dloam/drivers/huge_pages.hpp"

namespace dloam::drivers {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kBlocks = 12;
constexpr int kBlockSize = 100;
constexpr int kTurn = 36000;  // azimuth units (0.01 deg) per turn

std::uint16_t u16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

std::string hex(unsigned v, int width) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%0*X", width, v);
  return buf;
}

std::string where_of(const Packet& p) { return p.where.empty() ? std::string("packet") : p.where; }

[[noreturn]] void fail(const Packet& p, const std::string& what) {
  throw InputError(where_of(p) + ": " + what);
}

int bank_of(std::uint16_t flag) {
  switch (flag) {
    case kVelodyneBank1:
      return 0;
    case kVelodyneBank2:
      return 1;
    case kVelodyneBank3:
      return 2;
    case kVelodyneBank4:
      return 3;
    default:
      return -1;
  }
}

std::uint16_t block_flag(const Packet& p, int b) { return u16(p.data + b * kBlockSize); }
std::uint16_t block_azimuth(const Packet& p, int b) { return u16(p.data + b * kBlockSize + 2); }

bool is_dual(std::uint8_t mode) { return mode == kVelodyneDual; }

/// cos and sin of every azimuth step (0.01 deg), interleaved; built once. float: 288 KB that stay
/// in cache, 1e-5 m at 200 m.
const std::vector<float>& azimuth_table() {
  static const std::vector<float> table = [] {
    std::vector<float> t(2 * kTurn);
    for (int i = 0; i < kTurn; ++i) {
      const double a = i * 0.01 * kPi / 180.0;
      t[2 * static_cast<std::size_t>(i)] = static_cast<float>(std::cos(a));
      t[2 * static_cast<std::size_t>(i) + 1] = static_cast<float>(std::sin(a));
    }
    return t;
  }();
  return table;
}

/// Sinks with `static constexpr bool kOutline = true` are told each kept return's time only
/// (count(time)): its point is not computed.
template <class S, class = void>
struct counts_only : std::false_type {};
template <class S>
struct counts_only<S, std::void_t<decltype(S::kOutline)>> : std::bool_constant<S::kOutline> {};

std::string fmt(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Packet shape

bool looks_like_velodyne(const Packet& packet) {
  if (packet.data == nullptr || packet.size != kVelodyneDataPacketSize) return false;
  for (int b = 0; b < kBlocks; ++b) {
    if (bank_of(block_flag(packet, b)) >= 0) continue;
    // A dual-return VLS-128 packet uses blocks 0-7 only.
    const bool vls_dual = packet.data[1205] == 0xA1 && packet.data[1204] == kVelodyneDual;
    if (!(vls_dual && b >= 8)) return false;
  }
  return true;
}

bool is_velodyne_position_packet(const Packet& packet) {
  return packet.size == kVelodynePositionPacketSize &&
         (packet.port == 0 || packet.port == kVelodynePositionPort);
}

VelodynePacketHeader velodyne_packet_header(const Packet& packet) {
  VelodynePacketHeader h;
  h.toh_us = u32(packet.data + 1200);
  h.return_mode = packet.data[1204];
  h.product = packet.data[1205];
  return h;
}

// ---------------------------------------------------------------------------------------------
// Identification

namespace {

/// Median relative range difference |r[c] - r[c+16]| / max(r[c], r[c+16]) over the blocks of the
/// packets (both returns non-zero): small on a VLP-16, whose channels c and c + 16 are the same
/// laser 55 us apart, large on the 32-laser models (values on the recordings: docs/velodyne.md).
/// -1 when fewer than 50 pairs tell.
double channel_structure(const std::vector<const Packet*>& packets) {
  std::vector<double> rel;
  for (const Packet* p : packets)
    for (int b = 0; b < kBlocks; ++b) {
      const std::uint8_t* d = p->data + b * kBlockSize + 4;
      for (int c = 0; c < 16; ++c) {
        const int r0 = u16(d + 3 * c), r16 = u16(d + 3 * (c + 16));
        if (r0 > 0 && r16 > 0) rel.push_back(std::abs(r0 - r16) / static_cast<double>(std::max(r0, r16)));
      }
    }
  if (rel.size() < 50) return -1.0;
  std::nth_element(rel.begin(), rel.begin() + static_cast<std::ptrdiff_t>(rel.size() / 2), rel.end());
  return rel[rel.size() / 2];
}

/// 0: every block FF EE; 1: upper and lower blocks; 2: the VLS-128's four banks.
int block_layout(const Packet& p) {
  int layout = 0;
  for (int b = 0; b < kBlocks; ++b) {
    const int bank = bank_of(block_flag(p, b));
    if (bank >= 2) return 2;
    if (bank == 1) layout = 1;
  }
  return layout;
}

double nominal_packet_period_us(VelodyneModel m, std::uint8_t mode) {
  const VelodyneModelInfo& info = velodyne_model_info(m);
  int groups = kBlocks / info.blocks_per_group;
  if (is_dual(mode)) groups = m == VelodyneModel::kVLS128 ? 1 : groups / 2;
  return groups * info.group_period_us;
}

}  // namespace

VelodyneIdentification identify_velodyne(const std::vector<Packet>& packets) {
  std::vector<const Packet*> data;
  for (const Packet& p : packets)
    if (looks_like_velodyne(p)) data.push_back(&p);
  if (data.empty()) {
    const std::string where = packets.empty() ? std::string("Velodyne stream") : where_of(packets.front());
    throw InputError(where +
                     ": no Velodyne data packet (1206 bytes with block flags FF EE ...) among the first " +
                     std::to_string(packets.size()) + " packets; cannot identify the model");
  }
  const Packet& first = *data.front();
  VelodyneIdentification id;
  const int layout = block_layout(first);
  const VelodynePacketHeader h = velodyne_packet_header(first);
  if (layout == 2) {
    id.model = VelodyneModel::kVLS128;
    id.evidence = "block flags FF EE / FF DD / FF CC / FF BB";
    return id;
  }
  if (layout == 1) {
    id.model = VelodyneModel::kHDL64E_S2;
    id.evidence = "upper and lower blocks (FF EE / FF DD); S2 and S3 share the packet layout";
    return id;
  }
  // All blocks FF EE: VLP-16, VLP-32C or HDL-32E.
  std::vector<double> steps;
  for (std::size_t i = 1; i < data.size(); ++i) {
    const double dt = static_cast<double>(velodyne_packet_header(*data[i]).toh_us) -
                      static_cast<double>(velodyne_packet_header(*data[i - 1]).toh_us);
    if (dt > 0 && dt < 10000) steps.push_back(dt);
  }
  double step = -1.0;
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2),
                     steps.end());
    step = steps[steps.size() / 2];
  }
  const double ratio = channel_structure(data);
  const std::string product = hex(h.product, 2);
  std::string timing = step > 0 ? "TOH step " + fmt(step, 1) + " us" : "no TOH step (one packet)";
  std::string structure = ratio < 0
                              ? "too few returns to compare channels c and c+16"
                              : "channels c and c+16 " + std::string(ratio < 0.05 ? "alike" : "unlike") +
                                    " (median range difference " + fmt(ratio * 100.0, 1) + " %)";
  std::vector<VelodyneModel> by_timing;
  if (step > 0)
    for (VelodyneModel m : {VelodyneModel::kVLP16, VelodyneModel::kVLP32C, VelodyneModel::kHDL32E})
      if (std::abs(step - nominal_packet_period_us(m, h.return_mode)) <
          0.03 * nominal_packet_period_us(m, h.return_mode))
        by_timing.push_back(m);
  auto by_product = [&]() -> int {
    switch (h.product) {
      case 0x21:
        return static_cast<int>(VelodyneModel::kHDL32E);
      case 0x22:
      case 0x23:
      case 0x24:
        return static_cast<int>(VelodyneModel::kVLP16);
      case 0x28:
        return static_cast<int>(VelodyneModel::kVLP32C);
      default:
        return -1;
    }
  };
  const int prod = by_product();
  VelodyneModel chosen;
  if (by_timing.size() == 1) {
    chosen = by_timing.front();
  } else if (ratio >= 0) {
    // No timing (or several fits): the channel structure tells the VLP-16 from the 32-laser models.
    if (ratio < 0.05)
      chosen = VelodyneModel::kVLP16;
    else if (prod == static_cast<int>(VelodyneModel::kVLP32C) ||
             prod == static_cast<int>(VelodyneModel::kHDL32E))
      chosen = static_cast<VelodyneModel>(prod);
    else
      throw InputError(where_of(first) + ": cannot tell the Velodyne model (product byte " + product + ", " +
                       timing + ", " + structure + "); set the model (" + velodyne_model_names() + ")");
  } else if (prod >= 0) {
    chosen = static_cast<VelodyneModel>(prod);
  } else {
    throw InputError(where_of(first) + ": unknown Velodyne product byte " + product + " and " + timing +
                     " fits no model; set the model (" + velodyne_model_names() + ")");
  }
  id.model = chosen;
  id.evidence = timing + ", " + structure + ", product byte " + product;
  if (prod >= 0 && prod != static_cast<int>(chosen))
    id.evidence += " (which says " + std::string(velodyne_model_name(static_cast<VelodyneModel>(prod))) +
                   "; the timing and channel structure decide)";
  return id;
}

// ---------------------------------------------------------------------------------------------
// Packet decoder

VelodyneDecoder::VelodyneDecoder(VelodyneModel model, VelodyneCalibration calibration,
                                 const ScannerOptions& scan, const VelodyneOptions& options)
    : model_(model),
      info_(velodyne_model_info(model)),
      calibration_(std::move(calibration)),
      scan_(scan),
      options_(options) {
  if (calibration_.size() != info_.lasers)
    throw InputError(calibration_.source + ": the calibration has " + std::to_string(calibration_.size()) +
                     " lasers, the " + info_.name + " packets need " + std::to_string(info_.lasers));
  min_range_ = scan.min_range > 0 ? scan.min_range : info_.min_range_m;
  max_range_ = scan.max_range > 0 ? scan.max_range : info_.max_range_m;
  if (!(max_range_ > min_range_))
    throw InputError("Velodyne scanner: max_range " + fmt(max_range_, 3) + " must exceed min_range " +
                     fmt(min_range_, 3));
  auto units = [](double deg) { return static_cast<int>(std::lround(deg * 100.0)); };
  if (!(options.fov_min_deg >= 0 && options.fov_min_deg <= 360 && options.fov_max_deg >= 0 &&
        options.fov_max_deg <= 360))
    throw InputError("Velodyne scanner: the field of view bounds must be in [0, 360] deg");
  fov_min_ = units(options.fov_min_deg);
  fov_max_ = units(options.fov_max_deg);
  unit_f_ = static_cast<float>(info_.distance_unit_m);

  terms_.resize(calibration_.lasers.size());
  for (std::size_t i = 0; i < terms_.size(); ++i) {
    const VelodyneLaser& l = calibration_.lasers[i];
    LaserTerms& t = terms_[i];
    t.cos_vert = std::cos(l.vert_correction);
    t.sin_vert = std::sin(l.vert_correction);
    t.rot_units = l.rot_correction * 180.0 / kPi * 100.0;
    t.dist_corr = l.dist_correction;
    t.dist_corr_f = static_cast<float>(l.dist_correction);
    t.dist_corr_x = l.dist_correction_x;
    t.dist_corr_y = l.dist_correction_y;
    t.two_pt = l.two_pt_correction_available;
    t.vert_off = l.vert_offset_correction;
    t.horiz_off = l.horiz_offset_correction;
    const double f = 1.0 - l.focal_distance / 13100.0;
    t.focal_offset = 256.0 * f * f;
    t.focal_slope = l.focal_slope;
    t.min_int = l.min_intensity;
    t.max_int = l.max_intensity;
    t.ring = static_cast<std::uint16_t>(l.ring);
    t.simple = t.vert_off == 0.0 && t.horiz_off == 0.0 && !t.two_pt;
    t.clamp = t.min_int > 0.0 || t.max_int < 255.0 || t.focal_slope != 0.0;
  }
  const auto period = static_cast<float>(info_.group_period_us);
  for (int bank = 0; bank < 4; ++bank)
    for (int c = 0; c < 32; ++c) {
      const auto b = static_cast<std::size_t>(bank), ch = static_cast<std::size_t>(c);
      offset_us_[b][ch] = velodyne_channel_offset_us(model, bank, c);
      offset_s_[b][ch] = static_cast<double>(offset_us_[b][ch]) * 1e-6;
      fraction_[b][ch] = offset_us_[b][ch] / period;
      if (model == VelodyneModel::kVLS128) {
        // The manual's share of the 53.3 us sequence per firing group (2.665 / 53.3 per slot).
        const int g = velodyne_laser_of(model, bank, c) / 8;
        fraction_[b][ch] = (2.665f / 53.3f) * static_cast<float>(g + g / 8);
      }
      laser_[b][ch] =
          static_cast<std::uint16_t>(std::min(velodyne_laser_of(model, bank, c), info_.lasers - 1));
    }
  trig_ = azimuth_table().data();
  vlp16_ = model == VelodyneModel::kVLP16;
  period_f_ = static_cast<float>(info_.group_period_us);
  full_fov_ = fov_min_ == 0 && fov_max_ == kTurn;
}

int VelodyneDecoder::firings_per_packet(std::uint8_t return_mode) const {
  if (model_ == VelodyneModel::kVLP16) return is_dual(return_mode) ? 12 : 24;
  const int groups = kBlocks / info_.blocks_per_group;
  if (!is_dual(return_mode)) return groups;
  return model_ == VelodyneModel::kVLS128 ? 1 : groups / 2;
}

double VelodyneDecoder::packet_period_us(std::uint8_t return_mode) const {
  return nominal_packet_period_us(model_, return_mode);
}

template <class S>
[[gnu::always_inline]] inline void VelodyneDecoder::emit(std::uint16_t raw, std::uint8_t refl, int block,
                                                         int bank, int channel, int group,
                                                         std::uint16_t azimuth, float step, double group_time,
                                                         std::uint8_t return_id, bool last, S& sink) const {
  const auto b = static_cast<std::size_t>(bank), ch = static_cast<std::size_t>(channel);
  const std::uint16_t laser = laser_[b][ch];
  const LaserTerms& t = terms_[laser];
  float distance = static_cast<float>(raw) * unit_f_;
  distance += t.dist_corr_f;
  if (!(distance > min_range_ && distance < max_range_)) return;
  if constexpr (counts_only<S>::value) {
    if (full_fov_) {  // no azimuth needed
      sink.count(group_time + offset_s_[b][ch]);
      return;
    }
  }

  // Azimuth at this laser's firing, interpolated over the group's azimuth step, minus the laser's
  // azimuth correction, rounded to the encoder's 0.01 deg (the ROS drivers' float arithmetic).
  const float interp = vlp16_ ? (step * offset_us_[b][ch]) / period_f_ : step * fraction_[b][ch];
  const float az_f = static_cast<float>(azimuth) + interp;
  float corrected = static_cast<float>(static_cast<double>(az_f) - t.rot_units);
  if (corrected < 0.0f) corrected += static_cast<float>(kTurn);
  // Round half away from zero (corrected >= 0; exact in double).
  int az = static_cast<int>(static_cast<double>(corrected) + 0.5);
  if (az >= kTurn) az -= kTurn;
  if (!full_fov_ && !in_fov(az)) return;
  if constexpr (counts_only<S>::value) {
    sink.count(group_time + offset_s_[b][ch]);
  } else {
    VelodyneReturn r;
    const double cos_a = trig_[2 * az], sin_a = trig_[2 * az + 1];
    const double d = distance;
    if (t.simple) {
      const double xy = d * t.cos_vert;
      r.xyz = Vec3(xy * cos_a, -xy * sin_a, d * t.sin_vert);
    } else {
      // The ROS driver's model: beam origin offsets and the two-point distance correction.
      double xy = d * t.cos_vert - t.vert_off * t.sin_vert;
      double dcx = 0.0, dcy = 0.0;
      if (t.two_pt) {
        const double xx = std::abs(xy * sin_a - t.horiz_off * cos_a);
        const double yy = std::abs(xy * cos_a + t.horiz_off * sin_a);
        dcx = (t.dist_corr - t.dist_corr_x) * (xx - 2.4) / (25.04 - 2.4) + t.dist_corr_x - t.dist_corr;
        dcy = (t.dist_corr - t.dist_corr_y) * (yy - 1.93) / (25.04 - 1.93) + t.dist_corr_y - t.dist_corr;
      }
      const double dx = d + dcx, dy = d + dcy;
      xy = dx * t.cos_vert - t.vert_off * t.sin_vert;
      const double vx = xy * sin_a - t.horiz_off * cos_a;  // sensor frame x (right)
      xy = dy * t.cos_vert - t.vert_off * t.sin_vert;
      const double vy = xy * cos_a + t.horiz_off * sin_a;  // sensor frame y (forward)
      r.xyz = Vec3(vy, -vx, dy * t.sin_vert + t.vert_off * t.cos_vert);
    }
    double intensity = refl;
    if (t.focal_slope != 0.0) {
      const double s = 1.0 - raw / 65535.0;
      intensity += t.focal_slope * std::abs(t.focal_offset - 256.0 * s * s);
    }
    if (t.clamp) intensity = std::clamp(intensity, t.min_int, std::max(t.min_int, t.max_int));

    r.time = group_time + offset_s_[b][ch];
    r.range = distance;
    r.intensity = static_cast<float>(intensity);
    r.raw_distance = raw;
    r.azimuth = static_cast<std::uint16_t>(az);
    r.block_azimuth = azimuth;
    r.azimuth_step = step;
    r.time_in_group_us = offset_us_[b][ch];
    r.reflectivity = refl;
    r.block = static_cast<std::uint8_t>(block);
    r.channel = static_cast<std::uint8_t>(channel);
    r.group = static_cast<std::uint8_t>(group);
    r.laser = laser;
    r.ring = t.ring;
    r.return_id = return_id;
    r.last = last;
    sink.point(r);
  }
}

// Inlined into its one caller per sink type, so that a sink held there in a local (the outline
// counters) stays in registers.
template <class S>
[[gnu::always_inline]] inline void VelodyneDecoder::decode_packet(const Packet& packet, double hour_start,
                                                                  S& sink) {
  if (packet.data == nullptr || packet.size != kVelodyneDataPacketSize)
    fail(packet,
         "not a Velodyne data packet: " + std::to_string(packet.size) + " bytes (a data packet has 1206)");
  const VelodynePacketHeader h = velodyne_packet_header(packet);
  const bool hdl64 = model_ == VelodyneModel::kHDL64E_S2 || model_ == VelodyneModel::kHDL64E_S3;
  const std::uint8_t mode = hdl64 ? kVelodyneStrongest : h.return_mode;
  if (mode != kVelodyneStrongest && mode != kVelodyneLast && mode != kVelodyneDual)
    fail(packet, "unknown return mode byte " + hex(mode, 2) + " (0x37 strongest, 0x38 last, 0x39 dual)");
  const bool dual = is_dual(mode);
  if (dual && scan_.returns == ReturnMode::kFirst)
    fail(packet, "dual-return packet: a Velodyne reports the last and the strongest return, not the first");

  // Blocks used, the firing groups they form and the blocks' laser banks.
  const int used = (dual && model_ == VelodyneModel::kVLS128) ? 8 : kBlocks;
  const int per_group = (dual ? 2 : 1) * info_.blocks_per_group;  // blocks sharing one azimuth
  const int groups = used / per_group;
  std::array<int, kBlocks> bank{};
  for (int b = 0; b < used; ++b) {
    const std::uint16_t flag = block_flag(packet, b);
    const int k = bank_of(flag);
    int expected = 0;
    if (hdl64) expected = b % 2;
    if (model_ == VelodyneModel::kVLS128) expected = dual ? (b / 2) % 4 : b % 4;
    if (k != expected)
      fail(packet, "block " + std::to_string(b) + " has flag " + hex(flag, 4) + ", a " + info_.name + " " +
                       (dual ? "dual" : "single") + "-return packet has " +
                       hex(expected == 0   ? kVelodyneBank1
                           : expected == 1 ? kVelodyneBank2
                           : expected == 2 ? kVelodyneBank3
                                           : kVelodyneBank4,
                           4) +
                       " there");
    bank[static_cast<std::size_t>(b)] = k;
  }
  std::array<std::uint16_t, kBlocks> az{};
  for (int g = 0; g < groups; ++g) {
    const std::uint16_t a = block_azimuth(packet, g * per_group);
    // 36000 occurs at the wrap (VLP-16): the direction of 0, still the old turn.
    if (a > kTurn)
      fail(packet, "block " + std::to_string(g * per_group) + " azimuth " + std::to_string(a) +
                       " is not in 0..36000");
    az[static_cast<std::size_t>(g)] = a;
  }
  std::array<float, kBlocks> step{};
  for (int g = 0; g + 1 < groups; ++g)
    step[static_cast<std::size_t>(g)] = static_cast<float>(
        (az[static_cast<std::size_t>(g + 1)] - az[static_cast<std::size_t>(g)] + kTurn) % kTurn);
  step[static_cast<std::size_t>(groups - 1)] =
      groups >= 2 ? step[static_cast<std::size_t>(groups - 2)] : last_step_;
  last_step_ = step[static_cast<std::size_t>(groups - 1)];

  const double t0 = hour_start + h.toh_us * 1e-6 + info_.toh_to_first_us * 1e-6;
  for (int g = 0; g < groups; ++g) {
    const auto gi = static_cast<std::size_t>(g);
    const double group_time = t0 + g * info_.group_period_us * 1e-6;
    sink.group(g, az[gi], group_time);
    for (int k = 0; k < per_group; k += dual ? 2 : 1) {
      const int b = g * per_group + k;
      const std::uint8_t* d = packet.data + b * kBlockSize + 4;
      const int bk = bank[static_cast<std::size_t>(b)];
      if (!dual) {
        for (int c = 0; c < 32; ++c) {
          const std::uint16_t raw = u16(d + 3 * c);
          if (raw != 0) emit(raw, d[3 * c + 2], b, bk, c, g, az[gi], step[gi], group_time, 0, true, sink);
        }
        continue;
      }
      // Dual: block b holds the last return, block b + 1 the strongest (the second strongest
      // when the last is the strongest). A second return equal to the first is the same return.
      const std::uint8_t* o = d + kBlockSize;
      for (int c = 0; c < 32; ++c) {
        const std::uint16_t rl = u16(d + 3 * c), ro = u16(o + 3 * c);
        const std::uint8_t il = d[3 * c + 2], io = o[3 * c + 2];
        const bool other = ro != 0 && ro != rl;
        switch (scan_.returns) {
          case ReturnMode::kLast:
            if (rl != 0) emit(rl, il, b, bk, c, g, az[gi], step[gi], group_time, 0, true, sink);
            break;
          case ReturnMode::kStrongest:
          case ReturnMode::kFirst:
            if (other && (io > il || rl == 0))
              emit(ro, io, b + 1, bk, c, g, az[gi], step[gi], group_time, 0, false, sink);
            else if (rl != 0)
              emit(rl, il, b, bk, c, g, az[gi], step[gi], group_time, 0, true, sink);
            break;
          case ReturnMode::kAll:
            if (!other) {
              if (rl != 0) emit(rl, il, b, bk, c, g, az[gi], step[gi], group_time, 0, true, sink);
            } else if (rl != 0 && ro > rl) {  // unusual: the other return is farther
              emit(rl, il, b, bk, c, g, az[gi], step[gi], group_time, 0, true, sink);
              emit(ro, io, b + 1, bk, c, g, az[gi], step[gi], group_time, 1, false, sink);
            } else {
              emit(ro, io, b + 1, bk, c, g, az[gi], step[gi], group_time, 0, false, sink);
              if (rl != 0) emit(rl, il, b, bk, c, g, az[gi], step[gi], group_time, 1, true, sink);
            }
            break;
        }
      }
    }
  }
}

void VelodyneDecoder::decode(const Packet& packet, double hour_start, Sink& sink) {
  decode_packet(packet, hour_start, sink);
}

std::vector<VelodyneReturn> VelodyneDecoder::decode(const Packet& packet, double hour_start) {
  struct Collect : Sink {
    std::vector<VelodyneReturn> out;
    void group(int, std::uint16_t, double) override {}
    void point(const VelodyneReturn& r) override { out.push_back(r); }
  } collect;
  decode(packet, hour_start, collect);
  return std::move(collect.out);
}

// ---------------------------------------------------------------------------------------------
// Scanner: time base, rotations, sensor model

namespace detail {

class VelodyneScanner final : public Scanner {
 public:
  VelodyneScanner(VelodyneDecoder decoder, const DriverOptions& options, const VelodyneOptions& velodyne,
                  std::string evidence, std::string notes)
      : decoder_(std::move(decoder)),
        options_(options),
        velodyne_(velodyne),
        evidence_(std::move(evidence)),
        notes_(std::move(notes)) {
    expected_points_ = static_cast<std::size_t>(decoder_.calibration().size()) * 2048;
    cut_ = static_cast<int>(std::lround(
               std::fmod(std::fmod(options.scan.cut_azimuth_deg, 360.0) + 360.0, 360.0) * 100.0)) %
           kTurn;
  }

  void add(const Packet& packet, std::vector<Scan>& done) override {
    const std::size_t index = packets_++;
    if (is_velodyne_position_packet(packet)) {
      ++position_packets_;
      return;
    }
    if (packet.port == kVelodynePositionPort)
      fail(packet,
           "a Velodyne position packet (port 8308) has 512 bytes, this one " + std::to_string(packet.size));
    if (packet.size != kVelodyneDataPacketSize)
      fail(packet, "not a Velodyne packet: " + std::to_string(packet.size) +
                       " bytes (data packets have 1206, position packets 512)");
    const VelodynePacketHeader h = velodyne_packet_header(packet);
    const double toh = h.toh_us * 1e-6;
    if (data_packets_ == 0) {
      // The TOH counts µs since the top of the hour: take the hour from the recording time when
      // the sensor clock is synchronised to it (GPS / PTP), else anchor the counter to the first
      // packet's recording time.
      const double hour = std::floor((packet.stamp - toh) / 3600.0 + 0.5) * 3600.0;
      synced_ = std::abs(hour + toh - packet.stamp) < 2.0;
      base_ = synced_ ? hour : packet.stamp - toh;
      clock_offset_ = hour + toh - packet.stamp;
    } else if (toh + 1800.0 < prev_toh_) {
      base_ += 3600.0;  // the counter wrapped at the hour
    } else if (toh > prev_toh_ + 1800.0) {
      base_ -= 3600.0;  // a packet from before the wrap
    }
    const double toh_time = base_ + toh;
    if (data_packets_ > 0) {
      const double dt = toh_time - prev_time_;
      const double nominal = decoder_.packet_period_us(h.return_mode) * 1e-6;
      packet_gap_ = dt > 3.0 * nominal;
      if (dt > 0 && !packet_gap_) {
        const std::uint16_t a0 = block_azimuth_of(packet);
        sum_dt_ += dt;
        sum_az_ += (a0 - prev_az_ + kTurn) % kTurn;
        ++intervals_;
      }
    }
    mode_ = h.return_mode;
    product_ = h.product;
    prev_toh_ = toh;
    prev_time_ = toh_time;
    prev_az_ = block_azimuth_of(packet);
    ++data_packets_;
    index_ = index;
    done_ = &done;
    if (outline_) {
      Outline sink{*this};
      decoder_.decode_packet(packet, base_, sink);
      sink.flush();
    } else {
      make_room();
      decoder_.decode_packet(packet, base_, *this);
    }
    done_ = nullptr;
    packet_gap_ = false;
  }

  void finish(std::vector<Scan>& done) override {
    if (current_points() > 0) {
      current_.complete = false;
      done.push_back(take_current());
    }
    current_ = Scan{};
    written_ = 0;
    have_group_ = false;
  }

  [[nodiscard]] SensorConfig sensor() const override {
    const VelodyneCalibration& cal = decoder_.calibration();
    std::vector<const VelodyneLaser*> by_ring(cal.lasers.size());
    for (const VelodyneLaser& l : cal.lasers) by_ring[static_cast<std::size_t>(l.ring)] = &l;
    SensorConfig s;
    s.preset = velodyne_model_name(decoder_.model());
    s.N_scan = cal.size();
    bool offsets = false;
    for (const VelodyneLaser* l : by_ring) {
      s.beam_elevations_deg.push_back(l->vert_correction * 180.0 / kPi);
      s.beam_vertical_offsets_m.push_back(l->vert_offset_correction);
      offsets = offsets || l->vert_offset_correction != 0.0;
    }
    if (!offsets) s.beam_vertical_offsets_m.clear();
    s.Pit_bottom = s.beam_elevations_deg.front();
    s.fov_top = s.beam_elevations_deg.back();
    s.min_range = decoder_.min_range();
    s.max_range = decoder_.max_range();
    s.scan_rate_hz = rotation_hz();
    s.Horizon_SCAN = horizon_scan();
    return s;
  }

  bool outline_only(bool on) override {
    outline_ = on;
    return true;
  }

  [[nodiscard]] std::unique_ptr<Scanner> restart() const override {
    VelodyneDecoder decoder = decoder_;
    decoder.last_step_ = 0.0f;
    return std::make_unique<VelodyneScanner>(std::move(decoder), options_, velodyne_, evidence_, notes_);
  }

  [[nodiscard]] std::string describe() const override {
    std::ostringstream o;
    o << "Velodyne " << velodyne_model_name(decoder_.model());
    if (!evidence_.empty()) o << " (" << evidence_ << ")";
    if (data_packets_ > 0) {
      o << ", "
        << (mode_ == kVelodyneDual   ? "dual"
            : mode_ == kVelodyneLast ? "last"
                                     : "strongest")
        << " return";
      if (mode_ == kVelodyneDual)
        o << " (keeping "
          << (options_.scan.returns == ReturnMode::kAll    ? "both"
              : options_.scan.returns == ReturnMode::kLast ? "the last"
                                                           : "the strongest")
          << ")";
      if (intervals_ > 0) o << ", " << fmt(rotation_hz() * 60.0, 0) << " rpm";
      o << (synced_ ? ", TOH synchronised to the recording clock"
                    : ", TOH not synchronised (" + fmt(clock_offset_, 1) +
                          " s off): timed from the first packet");
    }
    o << ", calibration: " << decoder_.calibration().source;
    if (!notes_.empty()) o << " (" << notes_ << ")";
    o << ", " << data_packets_ << " data packets, " << position_packets_ << " position packets ignored";
    return o.str();
  }

 private:
  friend class dloam::drivers::VelodyneDecoder;  // calls group() and point()

  /// The decoder's sink in outline mode: the cut as with points, the returns only counted (here,
  /// and added to the scan at the next firing group and after the packet: flush()).
  struct Outline {
    static constexpr bool kOutline = true;
    VelodyneScanner& scanner;
    std::size_t points = 0;
    double end = -std::numeric_limits<double>::infinity();
    void group(int group, std::uint16_t azimuth, double time) {
      flush();
      scanner.group(group, azimuth, time);
    }
    void count(double time) {
      ++points;
      end = std::max(end, time);
    }
    void flush() {
      Scan& s = scanner.current_;
      s.outline_points += points;
      s.end = std::max(s.end, end);
      points = 0;
      end = -std::numeric_limits<double>::infinity();
    }
  };

  /// Points of the scan being assembled (decoded, or counted in outline mode).
  [[nodiscard]] std::size_t current_points() const { return written_ + current_.outline_points; }

  /// The scan being assembled, its arrays cut to the points written; a new one starts.
  Scan take_current() {
    current_.resize_points(written_);
    Scan out = std::move(current_);
    current_ = Scan{};
    written_ = 0;
    return out;
  }

  /// Points are written in place (point()): the arrays are kept at least a packet's returns
  /// ahead of the points written, sized up a chunk at a time within the reserved capacity.
  void make_room() {
    constexpr std::size_t kPacketReturns = kBlocks * 32;  // each return of a block at most once
    current_.make_room(written_, kPacketReturns);
  }
  static std::uint16_t block_azimuth_of(const Packet& p) { return block_azimuth(p, 0); }

  [[nodiscard]] double rotation_hz() const { return sum_dt_ > 0 ? sum_az_ / 100.0 / 360.0 / sum_dt_ : 10.0; }

  /// Firings per rotation at the nearest standard motor speed (a multiple of 60 rpm), rounded
  /// down to a multiple of 64: every column of the range image then holds a firing.
  [[nodiscard]] int horizon_scan() const {
    const std::uint8_t mode = data_packets_ > 0 ? mode_ : kVelodyneStrongest;
    // Packets per second as measured (a VLS-128 sends one every 164-168 us, not the 3 x 53.3 us
    // of its firing sequences), else nominal.
    const double packet_s =
        intervals_ > 0 ? sum_dt_ / static_cast<double>(intervals_) : decoder_.packet_period_us(mode) * 1e-6;
    const double firing_hz = decoder_.firings_per_packet(mode) / packet_s;
    const double rpm = std::max(60.0, std::round(rotation_hz()) * 60.0);
    const double per_turn = firing_hz / (rpm / 60.0);
    return std::clamp(static_cast<int>(per_turn / 64.0) * 64, 64, 16384);
  }

  /// True when the azimuth interval (from, to) (0.01 deg, forward) overlaps the field of view by
  /// more than one and a half packets' rotation at each end (a sensor sending part of the turn
  /// starts and stops at packet boundaries).
  [[nodiscard]] bool gap_in_fov(int from, int to) const {
    const int len = (to - from + kTurn) % kTurn;
    const double per_packet = intervals_ > 0 ? sum_az_ / static_cast<double>(intervals_) : 0.0;
    const int margin = std::max(100, static_cast<int>(1.5 * per_packet));
    for (int a = margin; a < len - margin; a += 50)
      if (decoder_.in_fov((from + a) % kTurn)) return true;
    return false;
  }

  // The decoder's sink.
  void group(int /*group*/, std::uint16_t azimuth, double time) {
    const int phased = azimuth >= cut_ ? azimuth - cut_ : azimuth - cut_ + kTurn;  // 0..36000
    bool lost = false;
    if (have_group_ && packet_gap_) lost = gap_in_fov(prev_group_az_, azimuth);
    if (have_group_ && prev_phased_ - phased > 1000) {
      // The azimuth passed the cut: the rotation is done.
      current_.complete = started_at_cut_ && !lost_ && !lost;
      expected_points_ = std::max(expected_points_, current_points() + current_points() / 8);
      done_->push_back(take_current());
      started_at_cut_ = true;
      lost_ = lost;
      fresh_ = true;
    } else if (lost) {
      lost_ = true;
    }
    if (!have_group_) started_at_cut_ = starts_rotation(azimuth);
    if (fresh_ || !have_group_) {
      current_.start = time;
      current_.end = time;
      current_.first_packet = index_;
      fresh_ = false;
      reserve();
      if (!outline_) make_room();
    }
    current_.last_packet = index_;
    current_.end = std::max(current_.end, time);
    have_group_ = true;
    prev_phased_ = phased;
    prev_group_az_ = azimuth;
  }

  /// Whether a recording whose first firing group has this azimuth starts with a whole
  /// rotation: within 1 deg after the cut, or, with a limited field of view, at most the largest
  /// azimuth correction + 2 deg after the window's start.
  [[nodiscard]] bool starts_rotation(int azimuth) const {
    const bool full = velodyne_.fov_min_deg <= 0.0 && velodyne_.fov_max_deg >= 360.0;
    if (full) return (azimuth - cut_ + kTurn) % kTurn <= 100;
    double max_rot = 0.0;
    for (const VelodyneLaser& l : decoder_.calibration().lasers)
      max_rot = std::max(max_rot, std::abs(l.rot_correction));
    const int window = static_cast<int>(std::lround(velodyne_.fov_min_deg * 100.0));
    const int after = ((azimuth - window) % kTurn + kTurn) % kTurn;
    return after <= static_cast<int>(std::lround((max_rot * 180.0 / kPi + 2.0) * 100.0));
  }

  void point(const VelodyneReturn& r) {
    const std::size_t k = written_++;  // make_room() made room for the packet
    current_.xyz[k] = r.xyz;
    current_.intensity[k] = r.intensity;
    current_.ring[k] = r.ring;
    current_.return_id[k] = r.return_id;
    current_.stamps[k] = r.time;
    current_.end = std::max(current_.end, r.time);
  }

  void reserve() {
    if (expected_points_ == 0 || outline_) return;
    current_.xyz.reserve(expected_points_);
    current_.intensity.reserve(expected_points_);
    current_.ring.reserve(expected_points_);
    current_.return_id.reserve(expected_points_);
    current_.stamps.reserve(expected_points_);
    advise_huge_pages(current_.xyz);
    advise_huge_pages(current_.stamps);
    advise_huge_pages(current_.intensity);
  }

  VelodyneDecoder decoder_;
  DriverOptions options_;
  VelodyneOptions velodyne_;
  std::string evidence_, notes_;
  int cut_ = 0;

  std::size_t packets_ = 0, data_packets_ = 0, position_packets_ = 0, index_ = 0;
  std::uint8_t mode_ = 0, product_ = 0;
  bool synced_ = false;
  double base_ = 0.0, clock_offset_ = 0.0, prev_toh_ = 0.0, prev_time_ = 0.0;
  int prev_az_ = 0;
  double sum_dt_ = 0.0, sum_az_ = 0.0;
  std::size_t intervals_ = 0;
  bool packet_gap_ = false;

  Scan current_;
  std::size_t written_ = 0;  ///< points of current_ (its arrays may be longer: make_room())
  std::vector<Scan>* done_ = nullptr;
  bool have_group_ = false, started_at_cut_ = false, lost_ = false, fresh_ = true;
  int prev_phased_ = 0, prev_group_az_ = 0;
  std::size_t expected_points_ = 0;
  bool outline_ = false;
};

}  // namespace detail

std::unique_ptr<Scanner> make_velodyne_scanner(const DriverOptions& options,
                                               const std::vector<Packet>& first_packets) {
  return make_velodyne_scanner(options, first_packets, VelodyneOptions{});
}

std::unique_ptr<Scanner> make_velodyne_scanner(const DriverOptions& options,
                                               const std::vector<Packet>& first_packets,
                                               const VelodyneOptions& velodyne) {
  VelodyneModel model;
  std::string evidence;
  if (!options.model.empty()) {
    const auto parsed = parse_velodyne_model(options.model);
    if (!parsed)
      throw InputError("unknown Velodyne model '" + options.model + "' (known: " + velodyne_model_names() +
                       ")");
    model = *parsed;
    evidence = "model given";
    // The packets must at least have this model's block layout.
    for (const Packet& p : first_packets) {
      if (!looks_like_velodyne(p)) continue;
      const int layout = block_layout(p);
      const bool hdl64 = model == VelodyneModel::kHDL64E_S2 || model == VelodyneModel::kHDL64E_S3;
      const int expected = model == VelodyneModel::kVLS128 ? 2 : hdl64 ? 1 : 0;
      if (layout != expected) {
        const char* kinds[] = {"all blocks FF EE (VLP-16, VLP-32C, HDL-32E)",
                               "upper and lower blocks (HDL-64E)", "four laser banks (VLS-128)"};
        throw InputError(where_of(p) + ": model " + velodyne_model_name(model) +
                         " was given, but the packet has " + kinds[layout]);
      }
      break;
    }
  } else {
    const VelodyneIdentification id = identify_velodyne(first_packets);
    model = id.model;
    evidence = id.evidence;
  }
  const VelodyneModelInfo& info = velodyne_model_info(model);
  VelodyneCalibration cal;
  if (!options.calibration.empty()) {
    cal = read_velodyne_calibration(options.calibration);
  } else if (!info.has_nominal_table) {
    throw InputError(
        std::string(info.name) +
        " packets need the unit's own calibration file (the ROS driver's YAML or VeloView's db.xml): "
        "the HDL-64E has no nominal angle table; set the calibration");
  } else {
    cal = nominal_velodyne_calibration(model);
  }
  std::string notes;
  if (cal.distance_resolution > 0 && std::abs(cal.distance_resolution - info.distance_unit_m) > 1e-9)
    notes = "its distance_resolution " + fmt(cal.distance_resolution, 4) + " m is not used: " + info.name +
            " packets count " + fmt(info.distance_unit_m * 1000.0, 0) + " mm";
  VelodyneDecoder decoder(model, std::move(cal), options.scan, velodyne);
  return std::make_unique<detail::VelodyneScanner>(std::move(decoder), options, velodyne, evidence, notes);
}

}  // namespace dloam::drivers
