// Plain data types shared by every module of the core library.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dloam {

using Vec3 = Eigen::Vector3d;
using Pose = Eigen::Isometry3d;  // sensor (or camera) frame -> world frame

/// One LiDAR sweep. Point order is the input's order and is preserved by every module,
/// so per-point outputs (labels, times) can be written back in the same order.
struct PointCloud {
  std::vector<Vec3> xyz;
  std::vector<float> intensity;  ///< same size as xyz, or empty
  std::vector<float> time;       ///< per-point time in [0, 1) of the sweep, or empty
  /// The scan's time (s: times.txt, a message stamp, the packets' clock), when known. Only
  /// differences between scans are used: the time between two scans scales the motion prior,
  /// the de-skew and the detection thresholds.
  std::optional<double> stamp;

  [[nodiscard]] std::size_t size() const { return xyz.size(); }
  [[nodiscard]] bool empty() const { return xyz.empty(); }
  [[nodiscard]] bool has_intensity() const { return intensity.size() == xyz.size(); }
  [[nodiscard]] bool has_time() const { return time.size() == xyz.size(); }
};

/// SemanticKITTI label: lower 16 bits class, upper 16 bits instance id.
using Label = std::uint32_t;
namespace semantic {
inline constexpr Label kUnlabeled = 0;
inline constexpr Label kOutlier = 1;
inline constexpr Label kStatic = 9;
inline constexpr Label kCar = 10;
inline constexpr Label kOtherVehicle = 20;
inline constexpr Label kPerson = 30;
inline constexpr Label kBicyclist = 31;
inline constexpr Label kMovingGeneric = 251;
inline constexpr Label kMovingCar = 252;
inline constexpr Label kMovingBicyclist = 253;
inline constexpr Label kMovingPerson = 254;
inline constexpr Label kMovingOtherVehicle = 259;
inline constexpr Label class_of(Label l) { return l & 0xFFFFu; }
inline constexpr std::uint32_t instance_of(Label l) { return l >> 16; }
inline constexpr Label make(Label cls, std::uint32_t instance) { return (instance << 16) | (cls & 0xFFFFu); }
/// MOS protocol classes (SemanticKITTI moving-object segmentation).
inline constexpr bool is_ignored(Label l) { return class_of(l) <= 1; }
inline constexpr bool is_moving(Label l) { return class_of(l) >= 251 && class_of(l) <= 259; }
}  // namespace semantic

/// Thrown for bad input (file, value); `what()` names the file and the problem.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace dloam
