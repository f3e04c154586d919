#include "dloam/drivers/ouster_metadata.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "dloam/core/types.hpp"

namespace dloam::drivers {

namespace {

using nlohmann::json;

/// Key paths of one layout.
struct Layout {
  std::vector<std::string> angles;       // object holding the beam angles and the origin offset
  std::vector<std::string> data_format;  // lidar_data_format / data_format
  std::vector<std::string> config;       // config_params / the root
  std::vector<std::string> sensor_info;  // sensor_info / the root
  std::vector<std::string> l2s;          // object holding lidar_to_sensor_transform
};

class Reader {
 public:
  Reader(const json& root, std::string source) : root_(root), source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(source_ + ": " + (key.empty() ? "" : key + ": ") + what);
  }

  /// The value at `path` + `key`, or nullptr when a part of the path is absent.
  const json* find(const std::vector<std::string>& path, const std::string& key) const {
    const json* v = &root_;
    for (const auto& p : path) {
      if (!v->is_object()) return nullptr;
      const auto it = v->find(p);
      if (it == v->end()) return nullptr;
      v = &*it;
    }
    if (!v->is_object()) {
      if (!path.empty()) fail(name(path, ""), "expected a JSON object");
      return nullptr;
    }
    const auto it = v->find(key);
    return it == v->end() ? nullptr : &*it;
  }

  static std::string name(const std::vector<std::string>& path, const std::string& key) {
    std::string n;
    for (const auto& p : path) n += (n.empty() ? "" : ".") + p;
    if (!key.empty()) n += (n.empty() ? "" : ".") + key;
    return n;
  }

  double number(const json& v, const std::string& key) const {
    if (!v.is_number()) fail(key, "expected a number, got " + type_of(v));
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(key, "not a finite number");
    return d;
  }

  long long integer(const json& v, const std::string& key) const {
    const double d = number(v, key);
    if (d != std::floor(d) || std::abs(d) > 9.0e15) fail(key, "expected an integer, got " + v.dump());
    return static_cast<long long>(d);
  }

  std::string string(const json& v, const std::string& key) const {
    if (!v.is_string()) fail(key, "expected a string, got " + type_of(v));
    return v.get<std::string>();
  }

  std::vector<double> numbers(const json& v, const std::string& key) const {
    if (!v.is_array()) fail(key, "expected an array of numbers, got " + type_of(v));
    std::vector<double> out;
    out.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i)
      out.push_back(number(v[i], key + "[" + std::to_string(i) + "]"));
    return out;
  }

  Eigen::Matrix4d transform(const json& v, const std::string& key) const {
    const auto m = numbers(v, key);
    if (m.size() != 16)
      fail(key, "expected 16 numbers (a row-major 4x4 matrix), got " + std::to_string(m.size()));
    Eigen::Matrix4d t;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) t(r, c) = m[static_cast<std::size_t>(4 * r + c)];
    if (t(3, 0) != 0.0 || t(3, 1) != 0.0 || t(3, 2) != 0.0 || t(3, 3) != 1.0)
      fail(key, "the last row must be 0 0 0 1");
    const Eigen::Matrix3d r = t.topLeftCorner<3, 3>();
    if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 ||
        r.determinant() < 0.0)
      fail(key, "the upper-left 3x3 block is not a rotation");
    return t;
  }

  static std::string type_of(const json& v) {
    if (v.is_null()) return "null";
    if (v.is_boolean()) return "a boolean";
    if (v.is_number()) return "a number";
    if (v.is_string()) return "a string \"" + v.get<std::string>() + "\"";
    if (v.is_array()) return "an array";
    return "an object";
  }

 private:
  const json& root_;
  std::string source_;
};

OusterProfile profile_of(const Reader& rd, const std::string& key, const std::string& name) {
  static const std::pair<const char*, OusterProfile> kNames[] = {
      {"LEGACY", OusterProfile::kLegacy},
      {"RNG19_RFL8_SIG16_NIR16", OusterProfile::kSingle},
      {"RNG19_RFL8_SIG16_NIR16_DUAL", OusterProfile::kDual},
      {"RNG15_RFL8_NIR8", OusterProfile::kLowDataRate},
      {"RNG15_RFL8_NIR8_DUAL", OusterProfile::kLowDataRateDual},
      {"FUSA_RNG15_RFL8_NIR8_DUAL", OusterProfile::kFusaLowDataRateDual},
  };
  std::string known;
  for (const auto& [n, p] : kNames) {
    if (name == n) return p;
    known += (known.empty() ? "" : ", ") + std::string(n);
  }
  rd.fail(key, "unsupported lidar profile \"" + name + "\" (supported: " + known + ")");
}

/// The run of decimal digits of `s` starting at `i`: its length, and its value in `value`
/// (saturated at 10^9, so that no run of digits overflows). No std::regex here: its matcher
/// recurses once per character and overflows the stack on long strings.
std::size_t digits_at(const std::string& s, std::size_t i, long long& value) {
  std::size_t n = 0;
  value = 0;
  while (i + n < s.size() && s[i + n] >= '0' && s[i + n] <= '9') {
    value = std::min<long long>(value * 10 + (s[i + n] - '0'), 1000000000LL);
    ++n;
  }
  return n;
}

bool starts_with_icase(const std::string& s, std::size_t i, const char* prefix) {
  for (; *prefix; ++prefix, ++i)
    if (i >= s.size() || std::toupper(static_cast<unsigned char>(s[i])) != *prefix) return false;
  return true;
}

/// Beams of a product line ("OS-0-128-U1", "OS1-64", "os-dome-32" -> 128, 64, 32), 0 when the
/// name does not say.
int beams_of_prod_line(const std::string& prod_line) {
  if (!starts_with_icase(prod_line, 0, "OS")) return 0;
  std::size_t i = 2;
  if (i < prod_line.size() && prod_line[i] == '-') ++i;
  bool model = false;
  for (const char* m : {"0-", "1-", "2-", "DOME-"}) {
    if (starts_with_icase(prod_line, i, m)) {
      i += std::char_traits<char>::length(m);
      model = true;
      break;
    }
  }
  long long beams = 0;
  if (!model || digits_at(prod_line, i, beams) == 0) return 0;
  return static_cast<int>(beams);
}

/// The first "vMAJOR.MINOR.PATCH" in `s` ("ousteros-image-prod-aries-v2.1.1+..." -> v2.1.1, 2).
bool find_version(const std::string& s, std::string& version, int& major) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != 'v') continue;
    std::size_t j = i + 1;
    long long number = 0, first = 0;
    bool ok = true;
    for (int part = 0; part < 3 && ok; ++part) {
      const std::size_t n = digits_at(s, j, number);
      if (part == 0) first = number;
      ok = n > 0 && (part == 2 || (j + n < s.size() && s[j + n] == '.'));
      j += n + (part < 2 ? 1 : 0);
    }
    if (!ok) continue;
    version = s.substr(i, j - i);
    major = static_cast<int>(first);
    return true;
  }
  return false;
}

/// "1024x10" -> 1024 columns at 10 Hz: 2 to 5 digits, 'x', 1 to 3 digits, nothing else.
bool parse_lidar_mode(const std::string& mode, int& columns, double& fps) {
  long long c = 0, f = 0;
  const std::size_t nc = digits_at(mode, 0, c);
  if (nc < 2 || nc > 5 || nc >= mode.size() || mode[nc] != 'x') return false;
  const std::size_t nf = digits_at(mode, nc + 1, f);
  if (nf < 1 || nf > 3 || nc + 1 + nf != mode.size()) return false;
  columns = static_cast<int>(c);
  fps = static_cast<double>(f);
  return true;
}

/// ouster-sdk's lidar_origin_to_beam_origin_mm when the file has none (per product line).
double default_beam_origin_mm(const std::string& prod_line) {
  if (prod_line.rfind("OS-0-", 0) == 0) return 27.67;
  if (prod_line.rfind("OS-1-", 0) == 0) return 15.806;
  if (prod_line.rfind("OS-2-", 0) == 0) return 13.762;
  return 12.163;  // first-generation sensors
}

/// ouster-sdk's pixel_shift_by_row when the file has none: the first-generation OS-1-64
/// stagger, repeated every 4 rows; rows past 64 get 0 (as the SDK pads).
std::vector<int> default_pixel_shift(int columns_per_frame, int pixels) {
  std::vector<int> shift(static_cast<std::size_t>(pixels), 0);
  int step = 0;
  switch (columns_per_frame) {
    case 512:
      step = 3;
      break;
    case 1024:
      step = 6;
      break;
    case 2048:
      step = 12;
      break;
    case 4096:
      step = 24;
      break;
    default:
      return shift;
  }
  for (int r = 0; r < std::min(pixels, 64); ++r) shift[static_cast<std::size_t>(r)] = step * (3 - r % 4);
  return shift;
}

}  // namespace

const char* to_string(OusterProfile profile) {
  switch (profile) {
    case OusterProfile::kLegacy:
      return "LEGACY";
    case OusterProfile::kSingle:
      return "RNG19_RFL8_SIG16_NIR16";
    case OusterProfile::kDual:
      return "RNG19_RFL8_SIG16_NIR16_DUAL";
    case OusterProfile::kLowDataRate:
      return "RNG15_RFL8_NIR8";
    case OusterProfile::kLowDataRateDual:
      return "RNG15_RFL8_NIR8_DUAL";
    case OusterProfile::kFusaLowDataRateDual:
      return "FUSA_RNG15_RFL8_NIR8_DUAL";
  }
  return "?";
}

int OusterMetadata::window_columns() const {
  if (column_window_first <= column_window_last) return column_window_last - column_window_first + 1;
  return column_window_last + 1 + columns_per_frame - column_window_first;
}

bool OusterMetadata::in_window(int m) const {
  if (column_window_first <= column_window_last) return m >= column_window_first && m <= column_window_last;
  return m >= column_window_first || m <= column_window_last;
}

int OusterMetadata::crc_expected() const {
  if (profile == OusterProfile::kLegacy || fusa_header) return 0;
  if (firmware_major < 0) return -1;
  return firmware_major >= 3 ? 1 : 0;
}

namespace {
OusterMetadata parse_metadata(const std::string& text, const std::string& source) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {  // syntax errors, and numbers out of range (406)
    throw InputError(source + ": not valid JSON: " + e.what());
  }
  if (!root.is_object()) throw InputError(source + ": expected a JSON object at the top level");
  const Reader rd(root, source);

  OusterMetadata md;
  md.source = source;
  for (const char* k :
       {"sensor_info", "beam_intrinsics", "lidar_intrinsics", "lidar_data_format", "config_params"})
    if (root.contains(k)) md.nested_layout = true;
  Layout L;
  if (md.nested_layout) {
    L = {
        {"beam_intrinsics"}, {"lidar_data_format"}, {"config_params"}, {"sensor_info"}, {"lidar_intrinsics"}};
  } else {
    L = {{}, {"data_format"}, {}, {}, {}};
  }
  auto get = [&](const std::vector<std::string>& path, const std::string& key) { return rd.find(path, key); };
  auto nm = [](const std::vector<std::string>& path, const std::string& key) {
    return Reader::name(path, key);
  };

  // Identity.
  if (const json* v = get(L.sensor_info, "prod_line"))
    md.prod_line = rd.string(*v, nm(L.sensor_info, "prod_line"));
  if (const json* v = get(L.sensor_info, "prod_sn")) {
    const std::string key = nm(L.sensor_info, "prod_sn");
    if (v->is_string()) {
      const std::string s = v->get<std::string>();
      if (!s.empty()) {
        if (s.find_first_not_of("0123456789") != std::string::npos || s.size() > 19)
          rd.fail(key, "expected a decimal serial number, got \"" + s + "\"");
        md.prod_sn = std::stoull(s);
      }
    } else {
      const long long sn = rd.integer(*v, key);
      if (sn < 0) rd.fail(key, "must not be negative");
      md.prod_sn = static_cast<std::uint64_t>(sn);
    }
  }
  if (const json* v = get(L.sensor_info, "initialization_id")) {
    const long long id = rd.integer(*v, nm(L.sensor_info, "initialization_id"));
    if (id < 0 || id > 0xFFFFFF) rd.fail(nm(L.sensor_info, "initialization_id"), "must fit in 24 bits");
    md.init_id = static_cast<std::uint32_t>(id);
  }
  for (const char* k : {"build_rev", "image_rev"}) {
    const json* v = get(L.sensor_info, k);
    if (v && v->is_string() && find_version(v->get<std::string>(), md.firmware, md.firmware_major)) break;
  }

  // Beam angles (required).
  const json* alt = get(L.angles, "beam_altitude_angles");
  const json* az = get(L.angles, "beam_azimuth_angles");
  if (!alt || !az) {
    const std::string missing = nm(L.angles, !alt ? "beam_altitude_angles" : "beam_azimuth_angles");
    rd.fail(missing, md.nested_layout ? "missing (required: the beam angles)"
                                      : "missing: neither the flat layout's beam angles nor the nested "
                                        "layout's beam_intrinsics (is this an Ouster metadata file?)");
  }
  md.beam_altitude_deg = rd.numbers(*alt, nm(L.angles, "beam_altitude_angles"));
  md.beam_azimuth_deg = rd.numbers(*az, nm(L.angles, "beam_azimuth_angles"));
  const int beams = static_cast<int>(md.beam_altitude_deg.size());
  if (beams < 2 || beams > 512)
    rd.fail(nm(L.angles, "beam_altitude_angles"), "expected 2 to 512 beams, got " + std::to_string(beams));
  if (md.beam_azimuth_deg.size() != md.beam_altitude_deg.size())
    rd.fail(nm(L.angles, "beam_azimuth_angles"), "has " + std::to_string(md.beam_azimuth_deg.size()) +
                                                     " entries, beam_altitude_angles " +
                                                     std::to_string(beams));
  for (std::size_t i = 0; i < md.beam_altitude_deg.size(); ++i) {
    if (std::abs(md.beam_altitude_deg[i]) >= 89.0)
      rd.fail(nm(L.angles, "beam_altitude_angles[" + std::to_string(i) + "]"), "must lie in (-89, 89) deg");
    if (std::abs(md.beam_azimuth_deg[i]) >= 180.0)
      rd.fail(nm(L.angles, "beam_azimuth_angles[" + std::to_string(i) + "]"), "must lie in (-180, 180) deg");
  }
  if (const int pb = beams_of_prod_line(md.prod_line); pb != 0 && pb != beams)
    rd.fail(nm(L.angles, "beam_altitude_angles"), "has " + std::to_string(beams) + " beams but " +
                                                      nm(L.sensor_info, "prod_line") + " is " + md.prod_line);

  // Lidar mode and data format.
  if (const json* v = get(L.config, "lidar_mode")) {
    md.lidar_mode = rd.string(*v, nm(L.config, "lidar_mode"));
    if (!parse_lidar_mode(md.lidar_mode, md.columns_per_frame, md.fps))
      rd.fail(nm(L.config, "lidar_mode"),
              "expected COLUMNSxRATE such as \"1024x10\", got \"" + md.lidar_mode + "\"");
  }
  const json* df = nullptr;
  if (const auto it = root.find(L.data_format[0]); it != root.end()) {
    df = &*it;
    if (!df->is_object()) rd.fail(L.data_format[0], "expected a JSON object, got " + Reader::type_of(*df));
  }
  auto df_key = [&](const char* k) { return nm(L.data_format, k); };
  auto df_get = [&](const char* k) -> const json* { return df ? get(L.data_format, k) : nullptr; };

  if (const json* v = df_get("columns_per_frame")) {
    const long long w = rd.integer(*v, df_key("columns_per_frame"));
    if (md.columns_per_frame != 0 && w != md.columns_per_frame)
      rd.fail(df_key("columns_per_frame"),
              std::to_string(w) + " contradicts " + nm(L.config, "lidar_mode") + " " + md.lidar_mode);
    if (w < 16 || w > 16384) rd.fail(df_key("columns_per_frame"), "must lie in [16, 16384]");
    md.columns_per_frame = static_cast<int>(w);
  }
  if (md.columns_per_frame == 0)
    rd.fail(nm(L.config, "lidar_mode"),
            "missing (required unless " + df_key("columns_per_frame") + " is given)");
  if (md.columns_per_frame < 16 || md.columns_per_frame > 16384)
    rd.fail(nm(L.config, "lidar_mode"), "columns must lie in [16, 16384]");
  if (const json* v = df_get("fps")) {
    const double f = rd.number(*v, df_key("fps"));
    if (md.fps == 0.0) md.fps = f;
  }
  if (!(md.fps > 0.0 && md.fps <= 100.0))
    rd.fail(nm(L.config, "lidar_mode"),
            md.fps == 0.0 ? "missing: the frame rate is unknown" : "frame rate out of range");

  md.pixels_per_column = beams;
  if (const json* v = df_get("pixels_per_column")) {
    const long long h = rd.integer(*v, df_key("pixels_per_column"));
    if (h != beams)
      rd.fail(df_key("pixels_per_column"),
              std::to_string(h) + " pixels but " + std::to_string(beams) + " beam angles");
  }
  if (const json* v = df_get("columns_per_packet")) {
    const long long c = rd.integer(*v, df_key("columns_per_packet"));
    if (c < 1 || c > md.columns_per_frame)
      rd.fail(df_key("columns_per_packet"), "must lie in [1, columns_per_frame]");
    md.columns_per_packet = static_cast<int>(c);
  } else if (const json* cv = get(L.config, "columns_per_packet"); cv && md.nested_layout) {
    const long long c = rd.integer(*cv, nm(L.config, "columns_per_packet"));
    if (c < 1 || c > md.columns_per_frame)
      rd.fail(nm(L.config, "columns_per_packet"), "must lie in [1, columns_per_frame]");
    md.columns_per_packet = static_cast<int>(c);
  }
  md.column_window_first = 0;
  md.column_window_last = md.columns_per_frame - 1;
  if (const json* v = df_get("column_window")) {
    const auto w = rd.numbers(*v, df_key("column_window"));
    if (w.size() != 2) rd.fail(df_key("column_window"), "expected [first, last]");
    for (const double c : w)
      if (c != std::floor(c) || c < 0 || c >= md.columns_per_frame)
        rd.fail(df_key("column_window"), "entries must be measurement ids in [0, columns_per_frame)");
    md.column_window_first = static_cast<int>(w[0]);
    md.column_window_last = static_cast<int>(w[1]);
  }
  if (const json* v = df_get("pixel_shift_by_row")) {
    const auto s = rd.numbers(*v, df_key("pixel_shift_by_row"));
    if (static_cast<int>(s.size()) != beams)
      rd.fail(df_key("pixel_shift_by_row"),
              "has " + std::to_string(s.size()) + " entries for " + std::to_string(beams) + " beams");
    for (const double x : s)
      if (x != std::floor(x) || std::abs(x) >= md.columns_per_frame)
        rd.fail(df_key("pixel_shift_by_row"), "entries must be integers of magnitude < columns_per_frame");
    for (const double x : s) md.pixel_shift_by_row.push_back(static_cast<int>(x));
  } else {
    md.pixel_shift_by_row = default_pixel_shift(md.columns_per_frame, beams);
  }

  // Profiles: lidar_data_format first, then config_params (nested layout).
  const json* prof = df_get("udp_profile_lidar");
  std::string prof_key = df_key("udp_profile_lidar");
  if (!prof && md.nested_layout) {
    prof = get(L.config, "udp_profile_lidar");
    prof_key = nm(L.config, "udp_profile_lidar");
  }
  if (prof) md.profile = profile_of(rd, prof_key, rd.string(*prof, prof_key));
  md.fusa_header = md.profile == OusterProfile::kFusaLowDataRateDual;
  if (const json* v = df_get("header_type")) {
    const std::string h = rd.string(*v, df_key("header_type"));
    if (h == "FUSA") {
      md.fusa_header = true;
    } else if (h == "STANDARD") {
      if (md.profile == OusterProfile::kFusaLowDataRateDual)
        rd.fail(df_key("header_type"), "STANDARD contradicts the profile FUSA_RNG15_RFL8_NIR8_DUAL");
      md.fusa_header = false;
    } else {
      rd.fail(df_key("header_type"), "expected STANDARD or FUSA, got \"" + h + "\"");
    }
  }
  if (md.profile == OusterProfile::kLegacy) md.fusa_header = false;
  const json* imu = df_get("udp_profile_imu");
  std::string imu_key = df_key("udp_profile_imu");
  if (!imu && md.nested_layout) {
    imu = get(L.config, "udp_profile_imu");
    imu_key = nm(L.config, "udp_profile_imu");
  }
  if (imu) {
    const std::string p = rd.string(*imu, imu_key);
    if (p == "LEGACY") {
      md.imu_profile_legacy = true;
    } else if (p == "ACCEL32_GYRO32_NMEA" || p == "OFF") {
      md.imu_profile_legacy = false;
      md.imu_packet_size = 0;
      if (const json* n = get({"imu_data_format"}, "imu_measurements_per_packet")) {
        const std::string key = "imu_data_format.imu_measurements_per_packet";
        const long long k = rd.integer(*n, key);
        if (k < 1 || k > 1000) rd.fail(key, "must lie in [1, 1000]");
        md.imu_packet_size = static_cast<int>(32 + 100 + 36 * k + 32);  // header, NMEA block, samples, footer
      }
    } else {
      rd.fail(imu_key, "unknown IMU profile \"" + p + "\"");
    }
  }
  if (const json* v = get(L.config, "return_order")) {
    const std::string o = rd.string(*v, nm(L.config, "return_order"));
    if (o == "STRONGEST_TO_WEAKEST") {
      md.return_order = OusterReturnOrder::kStrongestToWeakest;
    } else if (o == "NEAREST_TO_FARTHEST") {
      md.return_order = OusterReturnOrder::kNearestToFarthest;
    } else if (o == "FARTHEST_TO_NEAREST") {
      md.return_order = OusterReturnOrder::kFarthestToNearest;
    } else {
      rd.fail(nm(L.config, "return_order"), "unknown return order \"" + o + "\"");
    }
  }
  for (auto [key, port] :
       {std::pair{"udp_port_lidar", &md.udp_port_lidar}, std::pair{"udp_port_imu", &md.udp_port_imu}}) {
    const json* v = get(L.config, key);
    if (!v || v->is_null() || (v->is_string() && v->get<std::string>().empty())) continue;
    const long long p = rd.integer(*v, nm(L.config, key));
    if (p < 0 || p > 65535) rd.fail(nm(L.config, key), "not a UDP port");
    *port = static_cast<int>(p);
  }
  if (const json* v = get(L.config, "min_range_threshold_cm"); v && md.nested_layout) {
    const double cm = rd.number(*v, nm(L.config, "min_range_threshold_cm"));
    if (cm < 0) rd.fail(nm(L.config, "min_range_threshold_cm"), "must not be negative");
    md.min_range_threshold_m = cm / 100.0;
  }

  // Geometry.
  md.lidar_origin_to_beam_origin_mm = default_beam_origin_mm(md.prod_line);
  if (const json* v = get(L.angles, "lidar_origin_to_beam_origin_mm")) {
    md.lidar_origin_to_beam_origin_mm = rd.number(*v, nm(L.angles, "lidar_origin_to_beam_origin_mm"));
    if (std::abs(md.lidar_origin_to_beam_origin_mm) > 1000.0)
      rd.fail(nm(L.angles, "lidar_origin_to_beam_origin_mm"), "out of range (mm)");
  }
  md.beam_to_lidar = Eigen::Matrix4d::Identity();
  md.beam_to_lidar(0, 3) = md.lidar_origin_to_beam_origin_mm;
  if (const json* v = get(L.angles, "beam_to_lidar_transform"))
    md.beam_to_lidar = rd.transform(*v, nm(L.angles, "beam_to_lidar_transform"));
  md.lidar_to_sensor << -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1;
  if (const json* v = get(L.l2s, "lidar_to_sensor_transform"))
    md.lidar_to_sensor = rd.transform(*v, nm(L.l2s, "lidar_to_sensor_transform"));
  for (int i = 0; i < 3; ++i)
    if (std::abs(md.lidar_to_sensor(i, 3)) > 10000.0 || std::abs(md.beam_to_lidar(i, 3)) > 1000.0)
      rd.fail(nm(L.l2s, "lidar_to_sensor_transform"), "translation out of range (mm)");
  return md;
}
}  // namespace

OusterMetadata parse_ouster_metadata(const std::string& text, const std::string& source) {
  try {
    return parse_metadata(text, source);
  } catch (const json::exception& e) {  // a value of a type the reader did not expect
    throw InputError(source + ": " + e.what());
  }
}

OusterMetadata load_ouster_metadata(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the Ouster metadata file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(path + ": cannot read the Ouster metadata file");
  return parse_ouster_metadata(text.str(), path);
}

}  // namespace dloam::drivers
