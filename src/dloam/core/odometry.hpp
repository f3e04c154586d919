// LiDAR odometry (paper III.F, LeGO-LOAM's two-step LM): the sharp features of the current scan
// (f_e, f_p) are matched against all features of the previous scan (F_e, F_p). Step 1 uses the
// plane features for [t_z, roll, pitch], step 2 the edge features for [t_x, t_y, yaw]. With the
// dynamic-object detector on, the two-step estimate can run inside the RANSAC pseudo-static
// feature rejection (pseudo_static_rejection.hpp, N_pseudo, beta). Directions the features do not
// constrain (degeneracy.hpp) keep the motion prior, the constant-velocity prediction.
#pragma once

#include <memory>
#include <optional>

#include "dloam/core/registration.hpp"

namespace dloam {

/// III.F Odometry: two-step LM (planes -> tz, roll, pitch; edges -> tx, ty, yaw).
struct OdometryConfig {
  int max_iterations = 25;  ///< LM iterations per step
  /// m, nearest-feature search radius. The initial guess is T_coarse or the constant-velocity
  /// prediction, centimetres from the truth; LOAM's 5 m (no prior) lets repeated structure
  /// (fence posts, lamp rows) and unflagged traffic pull the estimate along the road.
  double max_correspondence = 2.0;
  /// An edge's match in the previous scan is a line when its 5 neighbours spread along it at least
  /// this many times more (variance) than across it (LOAM: 3).
  double edge_line_ratio = 3.0;
  bool weight_compensation = true;  ///< eq. 15
  /// deg: a sensor tilted more than this (its ground normal from its z axis) is registered in all
  /// six degrees of freedom at once instead of the two-step LM (handheld, legged platforms).
  double max_level_tilt_deg = 5.0;
  bool pseudo_static_rejection = true;
  int N_pseudo = 5;   ///< RANSAC iterations of pseudo-static rejection
  double beta = 0.1;  ///< fraction of worst-matching features removed per iteration
  double pseudo_inlier_distance =
      0.1;  ///< m: a feature with a larger residual is an outlier (stop when < beta are)
};

struct OdometryResult {
  Pose motion = Pose::Identity();  ///< T^{k -> k-1}: current scan frame -> previous scan frame
  RegistrationResult plane_step;
  RegistrationResult edge_step;
  /// The scan's features together (both steps' normal matrices added, all six degrees of
  /// freedom, at the estimate): degenerate when some direction of the motion is unconstrained;
  /// keeps_prior() when some of them kept the prior.
  Degeneracy degeneracy;
  bool initialized = false;  ///< false for the first scan (no previous features)
  int rejection_rounds = 0;  ///< pseudo-static rejection: estimates made (0 = not used)
  std::size_t rejected = 0;  ///< pseudo-static rejection: features removed
};

class ScanToScanOdometry {
 public:
  explicit ScanToScanOdometry(const OdometryConfig& config, const DegeneracyConfig& degeneracy = {})
      : config_(config), degeneracy_(degeneracy) {}

  /// `sharp`: f_e / f_p of the current scan with their weights; `all_edges` / `all_planes`:
  /// F_e / F_p of the current scan, kept as the next scan's target. `predicted`: initial motion.
  /// `with_rejection`: run the RANSAC pseudo-static rejection when the config enables it.
  OdometryResult process(const FeatureSource& sharp, std::vector<Vec3> all_edges,
                         std::vector<Vec3> all_planes, const Pose& predicted, bool with_rejection = false) {
    OdometryResult out = estimate(sharp, predicted, with_rejection);
    set_previous(std::move(all_edges), std::move(all_planes));
    return out;
  }
  /// The motion of `sharp` against the previous scan's features (predicted motion when none yet).
  /// `level`: the sensor's z axis is (close to) vertical, so the two-step LM applies; otherwise all
  /// six degrees of freedom are estimated together. `prior`: the motion kept along directions the
  /// features do not constrain (the constant-velocity prediction); none: every direction is
  /// estimated from `predicted` on (a guess that may be far off must not be kept anywhere), and
  /// the result's `degeneracy` only reports the unconstrained directions. `prior_error`: how far the
  /// prior can be off (the motion gate); directions where that exceeds degeneracy.max_prior_error
  /// are estimated from the features however weak (Degeneracy::held).
  [[nodiscard]] OdometryResult estimate(const FeatureSource& sharp, const Pose& predicted,
                                        bool with_rejection = false, bool level = true,
                                        const std::optional<Pose>& prior = std::nullopt,
                                        const PriorError& prior_error = {}) const;
  /// F_e / F_p of the current scan become the next scan's target.
  void set_previous(std::vector<Vec3> all_edges, std::vector<Vec3> all_planes);
  /// The previous scan's F_e / F_p, or null before the first scan.
  [[nodiscard]] const FeatureMap* previous() const { return previous_.get(); }

 private:
  OdometryConfig config_;
  DegeneracyConfig degeneracy_;
  std::unique_ptr<FeatureMap> previous_;
};

}  // namespace dloam
