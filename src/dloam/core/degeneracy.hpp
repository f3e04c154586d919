// Degeneracy of a registration (Zhang, Kaess & Singh, "On degeneracy of optimization-based state
// estimation problems", ICRA 2016): the eigen-decomposition of the normal matrix J^T W J of the
// point-to-line / point-to-plane residuals in a tangent space where translation and rotation have
// the same unit. A direction whose eigenvalue is small is not constrained by the geometry (the
// axis of a tunnel with smooth walls, travel and heading over an empty field): the registration
// keeps the motion prior there instead of its update (solution remapping, registration.hpp).
#pragma once

#include <array>
#include <string>

#include "dloam/core/se3.hpp"

namespace dloam {

/// `degeneracy:` section. The unit of an eigenvalue is one feature of weight 1 whose residual
/// changes one-to-one with the motion along the direction (a plane facing it, a line across it):
/// the eigenvalue counts how many features' worth of residual respond to a motion in that
/// direction. Rotations enter as the displacement they cause at `rotation_radius`. A direction is
/// degenerate (the prior is kept along it) when its eigenvalue is below min_features or, for a
/// direction mostly of translation, below min_fraction times the number of matched features (a
/// feature adds at most 1 to a translation; to a rotation, an amount that depends on the radius).
struct DegeneracyConfig {
  /// Features' worth below which a direction is unconstrained however many features matched.
  double min_features = 30.0;
  /// Share of the matched features' worth below which a direction is unconstrained: the few
  /// features that respond to it (lamps in a tunnel, a ring's noise taken for an edge) cannot
  /// outweigh the bias of the many that do not. 0 and min_features 0: never degenerate.
  double min_fraction = 0.08;
  double rotation_radius = 20.0;  ///< m: a rotation of 1/rotation_radius rad counts as 1 m of motion
  /// m: an unconstrained direction keeps the prior only where the prior itself can be off by less
  /// than this (PriorError along the direction, rotations at rotation_radius); along the others the
  /// data's estimate stands, weak as it is. Over 0.1 s a car's prior can be off by 0.3 m and 1 deg
  /// (0.35 m at 20 m): it is kept; a handheld scanner's by 10.5 deg (3.7 m): a turn that starts or
  /// stops within the interval is not replaced by the turn rate of the interval before.
  double max_prior_error = 1.0;
  /// The scan-to-map registration asks the odometry: a translation that only the share test
  /// (min_fraction) leaves unconstrained there is estimated from the map after all where the
  /// odometry's own features constrain it by at least this many features' worth (and its share,
  /// SecondOpinion). The map's share is small where its many ground and wall planes outnumber the
  /// few features along the road (a highway's posts); where the odometry, too, finds little along
  /// the direction (a tunnel) the map's few features are the noise the share test guards against.
  /// 0: the map's own tests decide.
  double odometry_min_features = 60.0;
};

/// A second, independent registration of the same motion (the odometry, scan to scan, beside the
/// scan-to-map registration): its normal matrix in the scaled twist coordinates of the first
/// registration's frame, and the features it matched.
struct SecondOpinion {
  Mat6 scaled_normal_matrix = Mat6::Zero();
  int matches = 0;
};

/// How far a motion prior can be from the truth (the motion gate: what the platform's accelerations
/// allow over the interval). Zero: exact (every unconstrained direction keeps it).
struct PriorError {
  double rotation = 0.0;     ///< rad
  double translation = 0.0;  ///< m
};

/// Degrees of freedom of the left perturbation [roll, pitch, yaw, tx, ty, tz] (twist order, target
/// frame axes; rotations about the current sensor position).
using DofMask = std::array<bool, 6>;
inline constexpr DofMask kAllDof = {true, true, true, true, true, true};
inline constexpr DofMask kPlaneStepDof = {true, true, false, false, false, true};  ///< roll, pitch, tz
inline constexpr DofMask kEdgeStepDof = {false, false, true, true, true, false};   ///< yaw, tx, ty

/// The eigen-decomposition of a normal matrix over its free degrees of freedom, in scaled twist
/// coordinates [rotation * rotation_radius (m); translation (m)].
struct Degeneracy {
  int free = 0;  ///< free degrees of freedom analysed
  /// Eigenvalues (features' worth; the first `free` are meaningful: the unconstrained ones first,
  /// then the others, each in ascending order) and their unit eigenvectors (columns, scaled twist
  /// coordinates, zero outside the free degrees of freedom).
  Vec6 eigenvalues = Vec6::Zero();
  Mat6 eigenvectors = Mat6::Zero();
  int unconstrained = 0;  ///< directions below the threshold (the first ones)
  /// Of those, the ones that keep the prior (the first ones): where it can be off by at most
  /// max_prior_error.
  int held = 0;
  int matches = 0;  ///< matched features behind the normal matrix
  [[nodiscard]] bool degenerate() const { return unconstrained > 0; }
  /// Some direction keeps the motion prior instead of the data's estimate.
  [[nodiscard]] bool keeps_prior() const { return held > 0; }
  /// The smallest eigenvalue (0 when nothing was analysed).
  [[nodiscard]] double weakest() const { return free > 0 ? eigenvalues.head(free).minCoeff() : 0.0; }
  /// The analysed normal matrix in scaled twist coordinates (zero outside the free degrees of freedom).
  [[nodiscard]] Mat6 scaled_normal_matrix() const {
    return eigenvectors.leftCols(free) * eigenvalues.head(free).asDiagonal() *
           eigenvectors.leftCols(free).transpose();
  }
  /// The unit eigenvector of the first unconstrained direction, else of the smallest eigenvalue.
  [[nodiscard]] Vec6 weakest_direction() const {
    Eigen::Index i = 0;
    if (unconstrained == 0 && free > 0) eigenvalues.head(free).minCoeff(&i);
    return eigenvectors.col(i);
  }
};

/// `H`: J^T W J of `matches` matched features over all six degrees of freedom in twist coordinates
/// [rad; m] (rotations about the sensor position). Only the degrees of freedom in `dof` are analysed.
/// `prior`: how far the prior that unconstrained directions would keep can be off (Degeneracy::held).
/// `second`: a translation below the share threshold only (not below min_features) counts as
/// constrained when the second registration constrains it (DegeneracyConfig::odometry_min_features).
Degeneracy analyse_degeneracy(const Mat6& H, int matches, const DofMask& dof, const DegeneracyConfig& config,
                              const PriorError& prior = {}, const SecondOpinion* second = nullptr);

/// The odometry's degeneracy (all six degrees of freedom, in the previous scan's frame) as a second
/// opinion in a frame rotated by `R` from it (the world frame of the scan-to-map registration:
/// R is the previous scan's world rotation). Both frames' twists are about the sensor position.
SecondOpinion second_opinion(const Degeneracy& odometry, const Eigen::Matrix3d& R);

/// [rotation; translation] (rad, m) -> scaled twist coordinates, and back.
Vec6 to_scaled(const Vec6& twist, const DegeneracyConfig& config);
Vec6 from_scaled(const Vec6& scaled, const DegeneracyConfig& config);
/// A normal matrix J^T W J in twist coordinates [rad; m] -> in scaled twist coordinates: D H D with
/// twist = D * scaled, D = diag(1/rotation_radius x 3, 1 x 3). (A gradient J^T W r goes the same
/// way, D g: from_scaled(g).)
Mat6 to_scaled_normal_matrix(const Mat6& H, const DegeneracyConfig& config);

/// The axis a scaled direction mostly moves along: "roll", "pitch", "yaw", "x", "y" or "z".
std::string direction_name(const Vec6& scaled);
/// The axes of the unconstrained directions, weakest first, joined by '+' ("" when none).
std::string unconstrained_names(const Degeneracy& d);

}  // namespace dloam
