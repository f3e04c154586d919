// LiDAR odometry (paper III.F, LeGO-LOAM's two-step LM): the sharp features of the current scan
// (f_e, f_p) are matched against all features of the previous scan (F_e, F_p). Step 1 uses the
// plane features for [t_z, roll, pitch], step 2 the edge features for [t_x, t_y, yaw].
#pragma once

#include <memory>

#include "dloam/core/registration.hpp"
#include "dloam/pipeline/config.hpp"

namespace dloam {

struct OdometryResult {
  Pose motion = Pose::Identity();  ///< T^{k -> k-1}: current scan frame -> previous scan frame
  RegistrationResult plane_step;
  RegistrationResult edge_step;
  bool initialized = false;  ///< false for the first scan (no previous features)
};

class ScanToScanOdometry {
 public:
  explicit ScanToScanOdometry(const OdometryConfig& config) : config_(config) {}

  /// `sharp`: f_e / f_p of the current scan with their weights; `all_edges` / `all_planes`:
  /// F_e / F_p of the current scan, kept as the next scan's target. `predicted`: initial motion.
  OdometryResult process(const FeatureSource& sharp, std::vector<Vec3> all_edges, std::vector<Vec3> all_planes,
                         const Pose& predicted);

 private:
  OdometryConfig config_;
  std::unique_ptr<FeatureMap> previous_;
};

}  // namespace dloam
