// KITTI / SemanticKITTI file formats: velodyne .bin scans, .label files, calib.txt, KITTI and
// TUM pose files, times.txt, and the camera <-> LiDAR frame change (sensor pose = Tr^-1 P Tr).
#include "dloam/io/kitti.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <set>
#include <sstream>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

using detail::fail;
using detail::fail_at;

namespace {
constexpr double kMaxRotationError = 1e-4;   // |R^T R - I| entries, generous for 9-10 digit files
constexpr double kMaxPoseTranslation = 1e9;  // m: UTM northings are ~1e7, Earth-centred coordinates ~6.4e6

/// Tr (velodyne -> camera 0); KITTI's object-detection calib files call it Tr_velo_to_cam.
bool is_tr_key(const std::string& key) { return key == "Tr" || key == "Tr_velo_to_cam"; }

void check_translation(const std::string& path, std::size_t line, const Vec3& t) {
  if (!(t.cwiseAbs().maxCoeff() <= kMaxPoseTranslation))
    fail_at(path, line,
            "translation (" + std::to_string(t.x()) + ", " + std::to_string(t.y()) + ", " +
                std::to_string(t.z()) + ") is farther than 1e9 m from the origin: not a pose");
}

void check_rotation(const std::string& path, std::size_t line, const Pose& pose) {
  const double err = detail::orthonormality_error(pose.linear());
  if (err > kMaxRotationError)
    fail_at(path, line,
            "rotation is not orthonormal (max |R^T R - I| = " + std::to_string(err) +
                ", det = " + std::to_string(pose.linear().determinant()) + ")");
}

/// Calls `row(values, line_number, line)` for every non-blank, non-comment line of `path`; a line
/// that is not `count` numbers is an InputError "expected <what>, got N" naming file and line.
template <class Row>
void for_each_row(const std::string& text, const std::string& path, std::size_t count,
                  const std::string& what, Row&& row) {
  const auto lines = detail::split_lines(text);
  std::vector<double> v;
  std::string error;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (detail::is_blank_or_comment(lines[i])) continue;
    if (!detail::parse_doubles(lines[i], v, error)) fail_at(path, i + 1, error);
    if (v.size() != count) fail_at(path, i + 1, "expected " + what + ", got " + std::to_string(v.size()));
    row(v, i + 1, lines[i]);
  }
}

std::string row_major_line(const Pose& pose) {
  std::string line;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      if (!line.empty()) line += ' ';
      line += detail::format_number(pose.matrix()(r, c));
    }
  return line;
}

/// Median of |f[k] - f[k + period]| over (a sample of) the float32 values: small when the
/// values `period` apart are the same field of neighbouring points.
double median_lag_difference(const std::string& bytes, std::size_t period) {
  const std::size_t n = bytes.size() / 4;
  if (n <= period) return 0.0;
  const std::size_t samples = std::min<std::size_t>(8192, n - period);
  const std::size_t stride = (n - period) / samples;
  std::vector<double> d;
  d.reserve(samples);
  for (std::size_t s = 0; s < samples; ++s) {
    const std::size_t k = s * stride;
    float a = 0.0f, b = 0.0f;
    std::memcpy(&a, bytes.data() + 4 * k, 4);
    std::memcpy(&b, bytes.data() + 4 * (k + period), 4);
    const double diff = std::abs(static_cast<double>(a) - static_cast<double>(b));
    if (std::isfinite(diff)) d.push_back(diff);
  }
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

/// Floats per record that the data looks like, when clearly not 4 (float32 x y z intensity): the
/// floats `p` apart (p = 5, 6, 8) differ far less than those 4 apart. Consecutive points of a sweep
/// are neighbours, so in genuine 16-byte records the values 4 apart are the closest; 5- or 6-float
/// records (x y z intensity ring [time]), PCL's padded 32-byte PointXYZI and float64 x y z intensity
/// (8 floats) show their own period instead. Unordered scans show none and pass.
std::size_t foreign_record_period(const std::string& bytes) {
  if (bytes.size() < 16 * 64) return 0;
  const double d4 = median_lag_difference(bytes, 4);
  for (const std::size_t p : {5, 6, 8})
    if (median_lag_difference(bytes, p) < 0.25 * d4) return p;
  return 0;
}
}  // namespace

PointCloud parse_kitti_bin(const std::string& bytes, const std::string& path) {
  if (bytes.empty()) fail(path, "empty scan (0 points)");
  if (bytes.size() % 16 != 0)
    fail(path, "size " + std::to_string(bytes.size()) +
                   " bytes is not a multiple of 16 (float32 x y z intensity per point); truncated file?");
  const std::size_t period = foreign_record_period(bytes);
  if (period != 0)
    fail(path, "does not look like float32 x y z intensity records (the values repeat every " +
                   std::to_string(period) + " floats: " + std::to_string(4 * period) +
                   "-byte records, or float64?)");
  const std::size_t n = bytes.size() / 16;
  PointCloud cloud;
  cloud.xyz.resize(n);
  cloud.intensity.resize(n);
  std::size_t tiny = 0;  // coordinates that are not 0 but below 1e-20 m: no LiDAR measures those
  for (std::size_t i = 0; i < n; ++i) {
    float p[4];
    std::memcpy(p, bytes.data() + 16 * i, sizeof(p));
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]) || !std::isfinite(p[3]))
      fail(path, "point " + std::to_string(i) + " of " + std::to_string(n) +
                     " has a NaN or Inf value (x y z i = " + std::to_string(p[0]) + " " +
                     std::to_string(p[1]) + " " + std::to_string(p[2]) + " " + std::to_string(p[3]) + ")");
    cloud.xyz[i] = Vec3(p[0], p[1], p[2]);
    cloud.intensity[i] = p[3];
    detail::check_point_distance(path, i, cloud.xyz[i]);
    for (int a = 0; a < 3; ++a) tiny += p[a] != 0.0f && std::abs(p[a]) < 1e-20f;
  }
  if (10 * tiny > n)
    fail(path, "does not look like float32 x y z intensity records (" + std::to_string(tiny) +
                   " coordinates are tiny non-zero numbers: float64 values?)");
  return cloud;
}

PointCloud read_kitti_bin(const std::string& path) { return parse_kitti_bin(read_file(path), path); }

void write_kitti_bin(const std::string& path, const PointCloud& cloud) {
  write_atomic(path, [&](std::ostream& out) {
    std::vector<float> buf(4 * cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      buf[4 * i + 0] = static_cast<float>(cloud.xyz[i].x());
      buf[4 * i + 1] = static_cast<float>(cloud.xyz[i].y());
      buf[4 * i + 2] = static_cast<float>(cloud.xyz[i].z());
      buf[4 * i + 3] = cloud.has_intensity() ? cloud.intensity[i] : 0.0f;
    }
    out.write(reinterpret_cast<const char*>(buf.data()), static_cast<std::streamsize>(buf.size() * 4));
  });
}

std::vector<Label> parse_labels(const std::string& bytes, const std::string& path,
                                std::size_t expected_points) {
  if (bytes.size() % 4 != 0)
    fail(path, "size " + std::to_string(bytes.size()) + " bytes is not a multiple of 4 (uint32 per point)");
  const std::size_t n = bytes.size() / 4;
  if (n != expected_points)
    fail(path, "has " + std::to_string(n) + " labels but the scan has " + std::to_string(expected_points) +
                   " points");
  std::vector<Label> labels(n);
  if (n > 0) std::memcpy(labels.data(), bytes.data(), bytes.size());
  return labels;
}

std::vector<Label> read_labels(const std::string& path, std::size_t expected_points) {
  return parse_labels(read_file(path), path, expected_points);
}

void write_labels(const std::string& path, const std::vector<Label>& labels) {
  write_atomic(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(labels.data()), static_cast<std::streamsize>(labels.size() * 4));
  });
}

Calib parse_calib(const std::string& text, const std::string& path) {
  Calib calib;
  const auto lines = detail::split_lines(text);
  std::set<std::string> seen;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (detail::is_blank_or_comment(lines[i])) continue;
    const auto colon = lines[i].find(':');
    if (colon == std::string::npos) fail_at(path, i + 1, "expected 'KEY: values', got '" + lines[i] + "'");
    const auto key_tokens = detail::split(std::string_view(lines[i]).substr(0, colon));
    if (key_tokens.size() != 1) fail_at(path, i + 1, "malformed key in '" + lines[i] + "'");
    const std::string key(key_tokens[0]);
    if (!seen.insert(is_tr_key(key) ? "Tr" : key).second)
      fail_at(
          path, i + 1,
          "duplicate key " + key + (is_tr_key(key) ? " (Tr and Tr_velo_to_cam are the same matrix)" : ""));
    std::vector<double> values;
    std::string error;
    if (!detail::parse_doubles(std::string_view(lines[i]).substr(colon + 1), values, error))
      fail_at(path, i + 1, key + ": " + error);
    if (values.empty()) fail_at(path, i + 1, key + ": no values");
    const bool is_matrix = is_tr_key(key) || (key.size() == 2 && key[0] == 'P');
    if (is_matrix && values.size() != 12)
      fail_at(path, i + 1, key + " needs 12 values (3x4 row-major), got " + std::to_string(values.size()));
    if (is_tr_key(key)) {
      calib.Tr = detail::pose_from_row_major(values.data());
      check_rotation(path, i + 1, calib.Tr);
      check_translation(path, i + 1, calib.Tr.translation());
      calib.has_Tr = true;
    }
    calib.entries.emplace_back(key, std::move(values));
  }
  return calib;
}

Calib read_calib(const std::string& path) { return parse_calib(read_file(path, kMaxConfigFileBytes), path); }

void write_calib(const std::string& path, const Calib& calib) {
  write_atomic(path, [&](std::ostream& out) {
    bool wrote_tr = false;
    for (const auto& [key, values] : calib.entries) {
      if (is_tr_key(key) && calib.has_Tr) {
        if (!wrote_tr) out << "Tr: " << row_major_line(calib.Tr) << '\n';
        wrote_tr = true;
        continue;
      }
      out << key << ':';
      for (double v : values) out << ' ' << detail::format_number(v);
      out << '\n';
    }
    if (calib.has_Tr && !wrote_tr) out << "Tr: " << row_major_line(calib.Tr) << '\n';
  });
}

std::vector<Pose> parse_kitti_poses(const std::string& text, const std::string& path) {
  std::vector<Pose> poses;
  for_each_row(text, path, 12, "12 numbers (3x4 row-major pose)",
               [&](const std::vector<double>& v, std::size_t line, const std::string&) {
                 poses.push_back(detail::pose_from_row_major(v.data()));
                 check_rotation(path, line, poses.back());
                 check_translation(path, line, poses.back().translation());
               });
  return poses;
}

std::vector<Pose> read_kitti_poses(const std::string& path) {
  return parse_kitti_poses(read_file(path, kMaxTableFileBytes), path);
}

void write_kitti_poses(const std::string& path, const std::vector<Pose>& poses) {
  write_atomic(path, [&](std::ostream& out) {
    for (const auto& pose : poses) out << row_major_line(pose) << '\n';
  });
}

std::vector<StampedPose> parse_tum_poses(const std::string& text, const std::string& path) {
  std::vector<StampedPose> poses;
  for_each_row(text, path, 8, "8 numbers (t tx ty tz qx qy qz qw)",
               [&](const std::vector<double>& v, std::size_t line, const std::string&) {
                 Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
                 if (!(std::abs(q.norm() - 1.0) <= 1e-3))
                   fail_at(path, line,
                           "quaternion is not unit length (norm " + std::to_string(q.norm()) + ")");
                 if (!poses.empty() && !(v[0] > poses.back().t))
                   fail_at(path, line,
                           "time " + detail::format_number(v[0]) + " is not later than the previous pose's " +
                               detail::format_number(poses.back().t));
                 StampedPose sp;
                 sp.t = v[0];
                 sp.pose.linear() = q.normalized().toRotationMatrix();
                 sp.pose.translation() = Vec3(v[1], v[2], v[3]);
                 check_translation(path, line, sp.pose.translation());
                 poses.push_back(sp);
               });
  return poses;
}

std::vector<StampedPose> read_tum_poses(const std::string& path) {
  return parse_tum_poses(read_file(path, kMaxTableFileBytes), path);
}

void write_tum_poses(const std::string& path, const std::vector<StampedPose>& poses) {
  write_atomic(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    for (const auto& sp : poses) {
      const Eigen::Quaterniond q(sp.pose.linear());
      const Vec3 t = sp.pose.translation();
      out << sp.t << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' ' << q.x() << ' ' << q.y() << ' '
          << q.z() << ' ' << q.w() << '\n';
    }
  });
}

std::vector<double> parse_times(const std::string& text, const std::string& path) {
  std::vector<double> times;
  for_each_row(text, path, 1, "one time in seconds",
               [&](const std::vector<double>& v, std::size_t line, const std::string& row) {
                 if (!times.empty() && !(v[0] > times.back()))
                   fail_at(path, line,
                           "time " + row + (v[0] == times.back() ? " equals" : " is earlier than") +
                               " the previous line's (scan times must increase)");
                 times.push_back(v[0]);
               });
  return times;
}

std::vector<double> read_times(const std::string& path) {
  return parse_times(read_file(path, kMaxTableFileBytes), path);
}

void write_times(const std::string& path, const std::vector<double>& times) {
  write_atomic(path, [&](std::ostream& out) {
    out << std::setprecision(17);
    for (double t : times) out << t << '\n';
  });
}

std::vector<Pose> camera_to_lidar(const std::vector<Pose>& camera_poses, const Pose& Tr) {
  const Pose Tr_inv = Tr.inverse();
  std::vector<Pose> out;
  out.reserve(camera_poses.size());
  for (const auto& P : camera_poses) out.push_back(Tr_inv * P * Tr);
  return out;
}

std::vector<Pose> lidar_to_camera(const std::vector<Pose>& lidar_poses, const Pose& Tr) {
  const Pose Tr_inv = Tr.inverse();
  std::vector<Pose> out;
  out.reserve(lidar_poses.size());
  for (const auto& L : lidar_poses) out.push_back(Tr * L * Tr_inv);
  return out;
}

std::string scan_name(std::size_t index) {
  std::ostringstream s;
  s << std::setw(6) << std::setfill('0') << index;
  return s.str();
}

}  // namespace dloam::io
