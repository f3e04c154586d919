// Hesai scanner: packet validation, loss accounting, timing, return selection, per-channel cut.
#include "dloam/drivers/hesai.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <sstream>

#include "dloam/core/enum_names.hpp"
#include "dloam/core/types.hpp"
#include "dloam/drivers/channel_cut.hpp"
#include "dloam/drivers/hesai_packet.hpp"
#include "dloam/drivers/stamp_alignment.hpp"

namespace dloam::drivers {

using hesai::Model;
using hesai::PacketView;

bool looks_like_hesai(const Packet& packet) { return hesai::looks_like_data_packet(packet); }

namespace {

constexpr int kMaxStep = 1000;  // 0.01 deg: azimuth steps counted for Horizon_SCAN

}  // namespace

struct HesaiScanner::Impl {
  struct Building {
    Scan scan;
    /// Points written in place into scan's arrays, which are kept a packet's returns longer
    /// (make_room) and cut to this when the scan is handed out.
    std::size_t written = 0;
    bool touched = false;  ///< a firing has been assigned to it
    bool complete = true;
  };

  Model model;
  const hesai::ModelInfo& info;
  hesai::Calibration calibration;
  ScannerOptions scan_options;
  HesaiOptions options;
  int channels;
  ChannelCut cut;
  StampAlignment clock;

  std::vector<std::uint16_t> ring;
  std::vector<double> cos_el, sin_el;
  // Per firing sequence (only the QT128 has two): azimuth offset cos / sin, firing offset (s).
  std::array<std::vector<double>, 2> off_cos, off_sin, fire_s;
  std::array<double, 2> fire_min{}, fire_max{};
  int angles_rpm = -1;  ///< motor speed the offset tables include (firing_time_azimuth)

  // Range checks in the decoder's float arithmetic (the sensor limits as float, the configured
  // ones as double), like nebula's, so that returns at the limits are kept or dropped alike.
  float sensor_min_f, sensor_max_f;
  double config_min, config_max;
  int raw_lo = 1, raw_hi = 0;  ///< valid raw distances at the distance unit raw_limits_mm
  int raw_limits_mm = -1;

  std::array<Building, 2> building;
  std::size_t counter = 0, decoded = 0, lost = 0, ignored = 0, corrupt = 0, reordered = 0;
  std::size_t dropped_since_good = 0;
  bool have_previous = false, previous_has_sequence = false, gap_pending = false;
  std::uint32_t previous_sequence = 0;
  double previous_sensor_time = 0.0;
  std::uint16_t previous_azimuth = 0;
  std::uint8_t last_mode = 0;
  int last_rpm = 0;
  std::array<std::size_t, kMaxStep + 1> step_histogram{};
  std::size_t mode_count = 0;
  int mode_step = 0;
  // Capacity reserved for a scan: the most a turn can hold (channels x returns x firings) until a
  // complete scan was seen, then 1/8 above the largest, so that points are not moved as it grows
  // (untouched capacity costs address space only).
  std::size_t reserve_points = 0, bound_points = 0, largest_complete = 0;
  bool outline = false;         ///< scans without points (Scanner::outline_only)
  std::size_t packet_room = 0;  ///< most returns of the packet being decoded

  static hesai::Calibration checked(hesai::Calibration c, Model m) {
    hesai::check_calibration(c, m);
    return c;
  }

  Impl(Model m, hesai::Calibration cal, const ScannerOptions& scan, const HesaiOptions& opt)
      : model(m),
        info(hesai::model_info(m)),
        calibration(checked(std::move(cal), m)),
        scan_options(scan),
        options(opt),
        channels(info.channels),
        cut(calibration.azimuth_deg, scan.cut_azimuth_deg) {
    if (!(options.multi_return_separation_m >= 0.0))
      throw InputError("Hesai: multi_return_separation_m must be >= 0");
    const auto n = static_cast<std::size_t>(channels);
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return calibration.elevation_deg[a] < calibration.elevation_deg[b];
    });
    ring.assign(n, 0);
    for (std::size_t r = 0; r < n; ++r) ring[order[r]] = static_cast<std::uint16_t>(r);
    for (std::size_t c = 0; c < n; ++c) {
      const double el = calibration.elevation_deg[c] * M_PI / 180.0;
      cos_el.push_back(std::cos(el));
      sin_el.push_back(std::sin(el));
    }
    for (int s = 0; s < 2; ++s) {
      fire_s[s].resize(n);
      for (std::size_t c = 0; c < n; ++c)
        fire_s[s][c] = hesai::channel_firing_offset_ns(model, static_cast<int>(c), s) * 1e-9;
      fire_min[s] = *std::min_element(fire_s[s].begin(), fire_s[s].end());
      fire_max[s] = *std::max_element(fire_s[s].begin(), fire_s[s].end());
    }
    build_angle_tables(0);
    sensor_min_f = static_cast<float>(info.min_range_m);
    sensor_max_f = static_cast<float>(info.max_range_m);
    config_min = scan.min_range > 0.0 ? scan.min_range : -std::numeric_limits<double>::infinity();
    config_max = scan.max_range > 0.0 ? scan.max_range : std::numeric_limits<double>::infinity();
    if (!(std::min(info.max_range_m, config_max) > std::max(info.min_range_m, config_min)))
      throw InputError("Hesai: the configured range [" + std::to_string(scan.min_range) + ", " +
                       std::to_string(scan.max_range) + "] m leaves nothing of the " + info.name + "'s [" +
                       std::to_string(info.min_range_m) + ", " + std::to_string(info.max_range_m) + "] m");
    building[0].complete = building[1].complete = false;
  }

  // Azimuth offset tables; with firing_time_azimuth they add each channel's firing offset turned
  // into an angle at `rpm`.
  void build_angle_tables(int rpm) {
    const double rad_per_s = options.firing_time_azimuth ? rpm * 2.0 * M_PI / 60.0 : 0.0;
    for (int s = 0; s < 2; ++s) {
      off_cos[s].resize(static_cast<std::size_t>(channels));
      off_sin[s].resize(static_cast<std::size_t>(channels));
      for (std::size_t c = 0; c < static_cast<std::size_t>(channels); ++c) {
        const double a = calibration.azimuth_deg[c] * M_PI / 180.0 + rad_per_s * fire_s[s][c];
        off_cos[s][c] = std::cos(a);
        off_sin[s][c] = std::sin(a);
      }
    }
    angles_rpm = rpm;
  }

  // Most frequent azimuth step between firings (0.01 deg); the model's at 600 rpm before any.
  [[nodiscard]] int step_cdeg() const {
    return mode_step > 0 ? mode_step : static_cast<int>(std::lround(info.step_deg_600 * 100.0));
  }

  void count_step(int d) {
    if (d < 1 || d > kMaxStep) return;
    const std::size_t n = ++step_histogram[static_cast<std::size_t>(d)];
    if (n > mode_count) {
      mode_count = n;
      mode_step = d;
    }
  }

  [[nodiscard]] double rpm() const { return last_rpm > 0 ? last_rpm : 600.0; }

  void reserve(Scan& s) const {
    if (outline) return;
    s.xyz.reserve(reserve_points);
    s.intensity.reserve(reserve_points);
    s.ring.reserve(reserve_points);
    s.return_id.reserve(reserve_points);
    s.stamps.reserve(reserve_points);
  }

  /// The arrays at least packet_room points longer than written (Scan::make_room).
  void make_room(Building& bl) const {
    if (!outline) bl.scan.make_room(bl.written, packet_room);
  }

  void reset_building(int b) {
    Building& bl = building[static_cast<std::size_t>(b)];
    bl.scan = Scan{};
    bl.written = 0;
    reserve(bl.scan);
    make_room(bl);
    bl.touched = false;
    bl.complete = true;
  }

  void emit(int b, std::vector<Scan>& done) {
    Building& bl = building[static_cast<std::size_t>(b)];
    const std::size_t points = bl.written + bl.scan.outline_points;  // decoded or counted
    if (points > 0) {
      bl.scan.resize_points(bl.written);
      bl.scan.complete = bl.complete;
      if (bl.complete) {
        largest_complete = std::max(largest_complete, points);
        reserve_points = std::min(bound_points, largest_complete + largest_complete / 8);
      }
      done.push_back(std::move(bl.scan));
    }
    reset_building(b);
  }

  // Ends both open scans (incomplete) and starts over at the next firing.
  void close_open(std::vector<Scan>& done) {
    const int first = cut.pending();
    building[static_cast<std::size_t>(first)].complete = false;
    building[static_cast<std::size_t>(first ^ 1)].complete = false;
    emit(first, done);
    emit(first ^ 1, done);
    building[0].complete = building[1].complete = false;
    cut.restart();
  }

  void touch(int b, std::size_t index, double start, double end) {
    Building& bl = building[static_cast<std::size_t>(b)];
    if (!bl.touched) {
      bl.touched = true;
      bl.scan.first_packet = index;
      bl.scan.start = start;
      bl.scan.end = end;
    }
    bl.scan.last_packet = index;
    bl.scan.start = std::min(bl.scan.start, start);
    bl.scan.end = std::max(bl.scan.end, end);
  }

  // Loss since the previous data packet; true when a rotation or more is missing.
  bool account_loss(const PacketView& v, int groups) {
    if (!have_previous) return false;
    const int step = step_cdeg();
    const double packets_per_rotation = 36000.0 / (groups * step);
    std::size_t missing = 0;
    bool long_gap = false;
    if (v.has_sequence && previous_has_sequence) {
      const std::uint32_t diff = v.sequence - previous_sequence;
      if (diff == 0 || diff >= 0x80000000u) {
        ++reordered;
      } else {
        missing = diff - 1;
        long_gap = static_cast<double>(missing) >= packets_per_rotation;
      }
    } else {
      const double dt = v.sensor_time - previous_sensor_time;
      const double interval = groups * step / 100.0 / (6.0 * rpm());
      if (dt > 1.5 * interval) missing = static_cast<std::size_t>(std::llround(dt / interval)) - 1;
      long_gap = dt >= 60.0 / rpm();
    }
    missing = missing > dropped_since_good ? missing - dropped_since_good : 0;
    if (missing > 0 || dropped_since_good > 0) gap_pending = true;
    lost += missing;
    dropped_since_good = 0;
    return long_gap;
  }

  [[nodiscard]] bool valid(std::uint16_t raw, float d) const {
    return raw != 0 && !(d < sensor_min_f) && !(sensor_max_f < d) && !(d < config_min) && !(config_max < d);
  }

  // The raw distances valid() accepts at the packet's distance unit: one interval, since the float
  // distance grows with the raw value.
  void set_raw_limits(const PacketView& v) {
    raw_lo = 1;
    raw_hi = 0;
    bool found = false;
    for (int r = 1; r <= 0xFFFF; ++r) {
      if (!valid(static_cast<std::uint16_t>(r), static_cast<float>(r * v.dis_unit_m))) continue;
      if (!found) raw_lo = r;
      raw_hi = r;
      found = true;
    }
    raw_limits_mm = v.dis_unit_mm;
  }

  void add(const Packet& packet, std::vector<Scan>& done) {
    const std::size_t index = counter++;
    if (hesai::is_gps_packet(packet)) {
      ++ignored;
      return;
    }
    const PacketView v = hesai::parse_packet(packet, model);
    if (v.crc_checked && !v.crc_ok) {
      ++corrupt;
      ++dropped_since_good;
      gap_pending = true;
      return;
    }
    const int n = v.layout.returns;
    const int groups = v.blocks / n;
    const bool long_gap = account_loss(v, groups);
    if (long_gap) {
      close_open(done);
      gap_pending = false;
    }
    // Azimuth steps (Horizon_SCAN), across packets only when none was lost in between.
    if (have_previous && !gap_pending && !long_gap)
      count_step((v.azimuth(0) - previous_azimuth + 36000) % 36000);
    for (int g = 1; g < groups; ++g) count_step((v.azimuth(g * n) - v.azimuth((g - 1) * n) + 36000) % 36000);
    have_previous = true;
    previous_has_sequence = v.has_sequence;
    previous_sequence = v.sequence;
    previous_sensor_time = v.sensor_time;
    previous_azimuth = v.azimuth((groups - 1) * n);
    last_mode = v.return_mode;
    last_rpm = v.motor_rpm;
    if (decoded++ == 0 || bound_points < static_cast<std::size_t>(channels * n) * (36000 / step_cdeg() + 1)) {
      bound_points = static_cast<std::size_t>(channels * n) * (36000 / step_cdeg() + 1);
      reserve_points = largest_complete > 0 ? std::min(bound_points, largest_complete + largest_complete / 8)
                                            : bound_points;
      for (Building& bl : building) reserve(bl.scan);
    }
    packet_room = static_cast<std::size_t>(channels) * static_cast<std::size_t>(v.blocks);
    for (Building& bl : building) make_room(bl);
    if (options.firing_time_azimuth && v.motor_rpm != angles_rpm) build_angle_tables(v.motor_rpm);

    if (v.dis_unit_mm != raw_limits_mm) set_raw_limits(v);
    const double packet_time = v.sensor_time + clock.update(packet.stamp, v.sensor_time);
    const ReturnMode want = scan_options.returns;
    for (int g = 0; g < groups; ++g) {
      const int b0 = g * n;
      const std::uint16_t raw_azimuth = v.azimuth(b0);
      const bool fresh = cut.fresh();
      const int pending = cut.pending();
      if (gap_pending && !fresh) {
        building[static_cast<std::size_t>(pending)].complete = false;
        if (cut.split()) building[static_cast<std::size_t>(pending ^ 1)].complete = false;
      }
      const ChannelCut::Step st = cut.step(raw_azimuth, gap_pending);
      if (fresh) {  // started mid-turn; a first firing across the cut starts the next scan late too
        building[0].complete = false;
        building[1].complete = !cut.split();
      }
      if (gap_pending && st.crossed) building[static_cast<std::size_t>(pending ^ 1)].complete = false;
      gap_pending = false;
      if (st.emitted >= 0) emit(st.emitted, done);

      int sequence = 0;
      if (model == Model::kPandarQT128) sequence = n == 1 ? (b0 % 2) : ((v.mode_flag & 0x01) ? 0 : 1);
      const auto s = static_cast<std::size_t>(sequence);
      const double t_group = packet_time + hesai::group_firing_offset_ns(model, g, groups) * 1e-9;
      if (cut.split()) {
        touch(0, index, t_group + fire_min[s], t_group + fire_max[s]);
        touch(1, index, t_group + fire_min[s], t_group + fire_max[s]);
      } else {
        touch(cut.buffer(0), index, t_group + fire_min[s], t_group + fire_max[s]);
      }
      const double azimuth = raw_azimuth * (M_PI / 18000.0);
      Firing f;
      f.sa = std::sin(azimuth);
      f.ca = std::cos(azimuth);
      f.t = t_group;
      f.oc = off_cos[s].data();
      f.os = off_sin[s].data();
      f.fs = fire_s[s].data();
      if (outline) {
        decode_firing<false>(v, b0, f, want);
      } else {
        decode_firing<true>(v, b0, f, want);
      }
    }
  }

  // Geometry and time of one firing, shared by its channels.
  struct Firing {
    double sa, ca;          ///< sin / cos of the block azimuth
    double t;               ///< time of the block group
    const double *oc, *os;  ///< cos / sin of each channel's azimuth offset
    const double* fs;       ///< each channel's firing offset (s)
  };

  /// Appends a return to `out`; kPoints false: counts it (an outline).
  template <bool kPoints>
  void push(Building& out, const Firing& f, std::size_t c, unsigned raw, double du, std::uint8_t refl,
            int k) const {
    if constexpr (!kPoints) {
      ++out.scan.outline_points;
      return;
    }
    const double d = raw * du;
    const double xy = d * cos_el[c];
    const double sin_az = f.sa * f.oc[c] + f.ca * f.os[c];
    const double cos_az = f.ca * f.oc[c] - f.sa * f.os[c];
    const std::size_t i = out.written++;  // make_room() made room for the packet
    Scan& s = out.scan;
    s.xyz[i] = Vec3(xy * cos_az, -xy * sin_az, d * sin_el[c]);
    s.stamps[i] = f.t + f.fs[c];
    s.intensity[i] = refl;
    s.ring[i] = ring[c];
    s.return_id[i] = static_cast<std::uint8_t>(k);
  }

  // The returns of every channel of the firing in blocks b0 .. b0 + returns - 1.
  template <bool kPoints>
  void decode_firing(const PacketView& v, int b0, const Firing& f, ReturnMode want) {
    if (raw_hi < raw_lo) return;  // no distance is in range
    const int n = v.layout.returns;
    const double du = v.dis_unit_m;
    const double separation = options.multi_return_separation_m;
    const std::uint8_t* u0 = v.unit(b0, 0);
    const std::size_t unit = v.unit_size, block = v.block_stride;
    const auto lo = static_cast<unsigned>(raw_lo), span = static_cast<unsigned>(raw_hi - raw_lo);
    auto in_range = [lo, span](unsigned raw) { return raw - lo <= span; };  // wraps below lo
    auto raw_at = [](const std::uint8_t* u) { return static_cast<unsigned>(u[0] | (u[1] << 8)); };
    const auto nc = static_cast<std::size_t>(channels);
    if (n == 1) {
      for (std::size_t c = 0; c < nc; ++c) {
        const std::uint8_t* u = u0 + unit * c;
        const unsigned r = raw_at(u);
        if (in_range(r)) push<kPoints>(building[cut.buffer(static_cast<int>(c))], f, c, r, du, u[2], 0);
      }
      return;
    }
    if (n == 2 && want == ReturnMode::kAll) {
      for (std::size_t c = 0; c < nc; ++c) {
        const std::uint8_t* u = u0 + unit * c;
        const unsigned r0 = raw_at(u), r1 = raw_at(u + block);
        const bool ok0 = in_range(r0), ok1 = in_range(r1);
        if (!ok0 && !ok1) continue;
        Building& out = building[cut.buffer(static_cast<int>(c))];
        // Block 0 is not the group's last: dropped when identical to or near block 1.
        if (ok0 && !(r0 == r1 && u[2] == u[block + 2]) &&
            !(static_cast<double>(std::fabs(static_cast<float>(r1 * du) - static_cast<float>(r0 * du))) <
              separation))
          push<kPoints>(out, f, c, r0, du, u[2], 0);
        if (ok1) push<kPoints>(out, f, c, r1, du, u[block + 2], 1);
      }
      return;
    }
    unsigned raw[3];
    std::uint8_t refl[3];
    bool ok[3];
    auto dist = [&](int k) { return static_cast<float>(raw[k] * du); };
    for (std::size_t c = 0; c < nc; ++c) {
      bool any = false;
      for (int k = 0; k < n; ++k) {
        const std::uint8_t* u = u0 + unit * c + block * static_cast<std::size_t>(k);
        raw[k] = raw_at(u);
        refl[k] = u[2];
        ok[k] = in_range(raw[k]);
        any = any || ok[k];
      }
      if (!any) continue;
      Building& out = building[cut.buffer(static_cast<int>(c))];
      if (want == ReturnMode::kAll) {
        for (int k = 0; k < n; ++k) {
          if (!ok[k]) continue;
          bool drop = false;
          if (k != n - 1) {
            for (int j = 0; j < n && !drop; ++j) {
              if (j == k) continue;
              drop = (raw[j] == raw[k] && refl[j] == refl[k]) ||
                     static_cast<double>(std::fabs(dist(j) - dist(k))) < separation;
            }
          }
          if (!drop) push<kPoints>(out, f, c, raw[k], du, refl[k], k);
        }
        continue;
      }
      int pick = want == ReturnMode::kFirst  ? v.layout.first
                 : want == ReturnMode::kLast ? v.layout.last
                                             : v.layout.strongest;
      if (pick == -2) pick = refl[0] >= refl[1] ? 0 : 1;
      if (pick == -1) {  // not in this mode: nearest / farthest / most reflective valid return
        for (int k = 0; k < n; ++k) {
          if (!ok[k]) continue;
          const bool better = pick < 0 || (want == ReturnMode::kFirst  ? raw[k] < raw[pick]
                                           : want == ReturnMode::kLast ? raw[k] > raw[pick]
                                                                       : refl[k] > refl[pick]);
          if (better) pick = k;
        }
      }
      if (pick >= 0 && ok[pick]) push<kPoints>(out, f, c, raw[pick], du, refl[pick], pick);
    }
  }
};

HesaiScanner::HesaiScanner(Model model, hesai::Calibration calibration, const ScannerOptions& scan,
                           const HesaiOptions& options)
    : impl_(std::make_unique<Impl>(model, std::move(calibration), scan, options)) {}

HesaiScanner::~HesaiScanner() = default;

void HesaiScanner::add(const Packet& packet, std::vector<Scan>& done) { impl_->add(packet, done); }

bool HesaiScanner::outline_only(bool on) {
  impl_->outline = on;
  return true;
}

std::unique_ptr<Scanner> HesaiScanner::restart() const {
  return std::make_unique<HesaiScanner>(impl_->model, impl_->calibration, impl_->scan_options,
                                        impl_->options);
}

void HesaiScanner::finish(std::vector<Scan>& done) {
  impl_->close_open(done);
  impl_->gap_pending = false;
  impl_->have_previous = false;
}

SensorConfig HesaiScanner::sensor() const {
  const Impl& m = *impl_;
  SensorConfig s;
  s.preset = m.info.name;
  s.N_scan = m.channels;
  s.beam_elevations_deg = m.calibration.elevation_deg;
  std::sort(s.beam_elevations_deg.begin(), s.beam_elevations_deg.end());
  s.beam_vertical_offsets_m.clear();
  s.Pit_bottom = s.beam_elevations_deg.front();
  s.fov_top = s.beam_elevations_deg.back();
  s.Horizon_SCAN = static_cast<int>(std::lround(36000.0 / m.step_cdeg()));
  s.min_range = std::max(m.info.min_range_m, m.scan_options.min_range);
  s.max_range = m.scan_options.max_range > 0.0 ? std::min(m.info.max_range_m, m.scan_options.max_range)
                                               : m.info.max_range_m;
  s.scan_rate_hz = m.rpm() / 60.0;
  return s;
}

std::string HesaiScanner::describe() const {
  const Impl& m = *impl_;
  std::ostringstream out;
  out << "Hesai " << m.info.name << ": ";
  if (m.decoded > 0) {
    char mode[8];
    std::snprintf(mode, sizeof(mode), "0x%02x", m.last_mode);
    out << hesai::return_layout(m.model, m.last_mode).name << " (" << mode << "), " << m.last_rpm << " rpm, ";
  }
  out << m.channels << " channels, angles from " << m.calibration.source << ", keeping "
      << name_of(m.scan_options.returns) << " returns; " << m.decoded << " packets decoded, " << m.lost
      << " lost, " << m.ignored << " ignored (GPS)";
  if (m.corrupt > 0) out << ", " << m.corrupt << " with a bad CRC (not decoded)";
  if (m.reordered > 0) out << ", " << m.reordered << " out of sequence";
  return out.str();
}

Model HesaiScanner::model() const { return impl_->model; }
const hesai::Calibration& HesaiScanner::calibration() const { return impl_->calibration; }
std::size_t HesaiScanner::packets() const { return impl_->decoded; }
std::size_t HesaiScanner::lost_packets() const { return impl_->lost; }
std::size_t HesaiScanner::ignored_packets() const { return impl_->ignored; }
std::size_t HesaiScanner::corrupt_packets() const { return impl_->corrupt; }
std::uint8_t HesaiScanner::return_mode() const { return impl_->last_mode; }
const std::vector<std::uint16_t>& HesaiScanner::rings() const { return impl_->ring; }

std::unique_ptr<HesaiScanner> make_hesai_scanner(const DriverOptions& options,
                                                 const std::vector<Packet>& first_packets,
                                                 const HesaiOptions& hesai_options) {
  Model model{};
  bool have_model = false;
  if (!options.model.empty()) {
    if (!hesai::parse_model(options.model, model))
      throw InputError("unknown Hesai model \"" + options.model + "\"; known: " + hesai::model_list());
    have_model = true;
  }
  for (const Packet& p : first_packets) {
    if (hesai::is_gps_packet(p)) continue;
    const Model seen = hesai::identify_model(p);
    if (have_model && seen != model)
      throw InputError((p.where.empty() ? std::string("Hesai packet") : p.where) + ": a " +
                       hesai::model_name(seen) + " packet, but the model is set to " +
                       hesai::model_name(model));
    model = seen;
    have_model = true;
    break;
  }
  if (!have_model)
    throw InputError("no Hesai data packet among the first " + std::to_string(first_packets.size()) +
                     " packets and no model given");
  hesai::Calibration calibration = options.calibration.empty() ? hesai::nominal_calibration(model)
                                                               : hesai::read_calibration(options.calibration);
  return std::make_unique<HesaiScanner>(model, std::move(calibration), options.scan, hesai_options);
}

std::unique_ptr<Scanner> make_hesai_scanner(const DriverOptions& options,
                                            const std::vector<Packet>& first_packets) {
  return make_hesai_scanner(options, first_packets, HesaiOptions{});
}

}  // namespace dloam::drivers
