// KITTI / SemanticKITTI file formats: velodyne .bin scans, .label files, calib.txt, KITTI and
// TUM pose files, times.txt, and the camera <-> LiDAR frame change (sensor pose = Tr^-1 P Tr).
#include "dloam/io/kitti.hpp"

#include <cmath>
#include <cstring>
#include <iomanip>
#include <sstream>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/text_util.hpp"

namespace dloam::io {

using detail::fail;
using detail::fail_at;

namespace {
constexpr double kMaxRotationError = 1e-4;  // |R^T R - I| entries, generous for 9-10 digit files

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
void for_each_row(const std::string& path, std::size_t count, const std::string& what, Row&& row) {
  const auto lines = detail::read_lines(path);
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
}  // namespace

PointCloud read_kitti_bin(const std::string& path) {
  const std::string bytes = read_file(path);
  if (bytes.empty()) fail(path, "empty scan (0 points)");
  if (bytes.size() % 16 != 0)
    fail(path, "size " + std::to_string(bytes.size()) +
                   " bytes is not a multiple of 16 (float32 x y z intensity per point); truncated file?");
  const std::size_t n = bytes.size() / 16;
  PointCloud cloud;
  cloud.xyz.resize(n);
  cloud.intensity.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    float p[4];
    std::memcpy(p, bytes.data() + 16 * i, sizeof(p));
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]) || !std::isfinite(p[3]))
      fail(path, "point " + std::to_string(i) + " of " + std::to_string(n) +
                     " has a NaN or Inf value (x y z i = " + std::to_string(p[0]) + " " +
                     std::to_string(p[1]) + " " + std::to_string(p[2]) + " " + std::to_string(p[3]) + ")");
    cloud.xyz[i] = Vec3(p[0], p[1], p[2]);
    cloud.intensity[i] = p[3];
  }
  return cloud;
}

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

std::vector<Label> read_labels(const std::string& path, std::size_t expected_points) {
  const std::string bytes = read_file(path);
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

void write_labels(const std::string& path, const std::vector<Label>& labels) {
  write_atomic(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(labels.data()), static_cast<std::streamsize>(labels.size() * 4));
  });
}

Calib read_calib(const std::string& path) {
  Calib calib;
  const auto lines = detail::read_lines(path);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (detail::is_blank_or_comment(lines[i])) continue;
    const auto colon = lines[i].find(':');
    if (colon == std::string::npos) fail_at(path, i + 1, "expected 'KEY: values', got '" + lines[i] + "'");
    const auto key_tokens = detail::split(std::string_view(lines[i]).substr(0, colon));
    if (key_tokens.size() != 1) fail_at(path, i + 1, "malformed key in '" + lines[i] + "'");
    const std::string key(key_tokens[0]);
    std::vector<double> values;
    std::string error;
    if (!detail::parse_doubles(std::string_view(lines[i]).substr(colon + 1), values, error))
      fail_at(path, i + 1, key + ": " + error);
    if (values.empty()) fail_at(path, i + 1, key + ": no values");
    const bool is_matrix = key == "Tr" || (key.size() == 2 && key[0] == 'P');
    if (is_matrix && values.size() != 12)
      fail_at(path, i + 1, key + " needs 12 values (3x4 row-major), got " + std::to_string(values.size()));
    if (key == "Tr") {
      calib.Tr = detail::pose_from_row_major(values.data());
      check_rotation(path, i + 1, calib.Tr);
      calib.has_Tr = true;
    }
    calib.entries.emplace_back(key, std::move(values));
  }
  return calib;
}

void write_calib(const std::string& path, const Calib& calib) {
  write_atomic(path, [&](std::ostream& out) {
    bool wrote_tr = false;
    for (const auto& [key, values] : calib.entries) {
      if (key == "Tr" && calib.has_Tr) {
        out << "Tr: " << row_major_line(calib.Tr) << '\n';
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

std::vector<Pose> read_kitti_poses(const std::string& path) {
  std::vector<Pose> poses;
  for_each_row(path, 12, "12 numbers (3x4 row-major pose)",
               [&](const std::vector<double>& v, std::size_t line, const std::string&) {
                 poses.push_back(detail::pose_from_row_major(v.data()));
                 check_rotation(path, line, poses.back());
               });
  return poses;
}

void write_kitti_poses(const std::string& path, const std::vector<Pose>& poses) {
  write_atomic(path, [&](std::ostream& out) {
    for (const auto& pose : poses) out << row_major_line(pose) << '\n';
  });
}

std::vector<StampedPose> read_tum_poses(const std::string& path) {
  std::vector<StampedPose> poses;
  for_each_row(path, 8, "8 numbers (t tx ty tz qx qy qz qw)",
               [&](const std::vector<double>& v, std::size_t line, const std::string&) {
                 Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
                 if (std::abs(q.norm() - 1.0) > 1e-3)
                   fail_at(path, line,
                           "quaternion is not unit length (norm " + std::to_string(q.norm()) + ")");
                 StampedPose sp;
                 sp.t = v[0];
                 sp.pose.linear() = q.normalized().toRotationMatrix();
                 sp.pose.translation() = Vec3(v[1], v[2], v[3]);
                 poses.push_back(sp);
               });
  return poses;
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

std::vector<double> read_times(const std::string& path) {
  std::vector<double> times;
  for_each_row(path, 1, "one time in seconds",
               [&](const std::vector<double>& v, std::size_t line, const std::string& text) {
                 if (!times.empty() && v[0] < times.back())
                   fail_at(path, line, "time " + text + " is earlier than the previous line's");
                 times.push_back(v[0]);
               });
  return times;
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
