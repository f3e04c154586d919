// Pre-registration (paper III.D.1): PCA of the segmented clusters picks static-looking vertical
// reference objects, pole-like (eqs. 8-9) and vertical planes (eqs. 10-11); a trimmed ICP run
// N_coarse times between the object sets of adjacent scans, each time discarding the worst
// trim_ratio of the correspondences, gives the coarse inter-scan motion T_coarse.
#pragma once

#include <functional>
#include <vector>

#include "dloam/core/motion_model.hpp"
#include "dloam/core/registration.hpp"
#include "dloam/core/segmentation.hpp"

namespace dloam {

/// III.D.1 Pre-registration: PCA pole/plane objects, RANSAC/ICP between adjacent scans.
struct PreRegistrationConfig {
  bool enabled = true;
  int N_PCA = 30;
  double xi_1 = 0.85;       ///< pole: normalised lambda_1 above
  double xi_2 = 0.1;        ///< pole: normalised lambda_2 (~lambda_3) below
  double xi_3 = 0.95;       ///< pole: |e_1 . n_ground| above
  double xi_4 = 0.1;        ///< plane: normalised lambda_3 below
  double xi_5 = 0.05;       ///< plane: |e_3 . n_ground| below (normal is horizontal)
  int N_coarse = 5;         ///< RANSAC iterations of ICP
  double trim_ratio = 0.1;  ///< worst fraction discarded per iteration
  /// dloam's addition: T_coarse refined by a projective point-to-plane alignment of the current
  /// scan onto the previous range image (core/range_alignment.hpp). Eq. 13 needs the motion to a
  /// few centimetres; the objects of a 16-beam scan give it to a decimetre and a degree.
  bool refine = true;
};

enum class ObjectShape { kOther, kPole, kPlane };

/// PCA of a point set: eigenvalues normalised to sum 1, descending (lambda_1 >= lambda_2 >= lambda_3),
/// and the matching unit eigenvectors e_1, e_2, e_3.
struct Pca {
  Vec3 lambda = Vec3::Zero();
  Vec3 e1 = Vec3::UnitX(), e2 = Vec3::UnitY(), e3 = Vec3::UnitZ();
};
Pca principal_components(const std::vector<Vec3>& points);

/// Eqs. 8-11 with the normalised eigenvalues: a pole has lambda_1 > xi_1, lambda_2 < xi_2 and
/// |e_1 . n| > xi_3; a vertical plane has lambda_3 < xi_4, lambda_2 >= xi_2 (not a line) and a
/// horizontal normal, |e_3 . n| < xi_5. Fewer than N_PCA points: kOther.
ObjectShape classify_object(const std::vector<Vec3>& points, const Vec3& ground_normal,
                            const PreRegistrationConfig& config);

/// The object set O of a scan: points (one per range-image pixel, voxel-downsampled with `leaf`)
/// of the clusters classified as poles (edges of the ICP) and vertical planes (planes).
struct ObjectSet {
  std::vector<Vec3> poles;
  std::vector<Vec3> planes;
  int num_poles = 0, num_planes = 0;  ///< classified clusters
  [[nodiscard]] std::size_t size() const { return poles.size() + planes.size(); }
};
ObjectSet extract_objects(const std::vector<Vec3>& points, const SegmentationResult& seg,
                          const PreRegistrationConfig& config, double leaf = 0.3);

struct CoarseResult {
  Pose T = Pose::Identity();  ///< source (current scan) -> target (previous scan)
  bool valid = false;         ///< enough matched, non-degenerate correspondences
  int matches = 0;            ///< matched correspondences at the last iteration
  std::size_t kept = 0;       ///< source points left after trimming
};

/// Trimmed ICP (the paper's "RANSAC" of pre-registration): `iterations` rounds of point-to-line /
/// point-to-plane registration (registration.hpp) from `initial`; after each round the worst
/// `trim_ratio` of the still-used source points (unmatched first, then largest residual) are dropped.
CoarseResult trimmed_registration(const FeatureSource& source, const FeatureMap& target, const Pose& initial,
                                  int iterations, double trim_ratio, const RegistrationParams& params);

/// The first scan pair has no motion prior: the pose translation(dx) * `initial` (dx along the
/// sensor's x axis, the driving direction, in [-range, range] by `step`) with the highest `score`
/// (ties: the smallest |dx|). `score` is called concurrently (the candidates in parallel).
Pose search_forward_translation(const Pose& initial, double range, double step,
                                const std::function<double(const Pose&)>& score);
/// The same over turns as well: translation(dx) * `initial` * yaw(a), a in [-yaw_range, yaw_range]
/// by `yaw_step` (rad); ties: the smallest |a|, then the smallest |dx|.
Pose search_planar_motion(const Pose& initial, double range, double step, double yaw_range, double yaw_step,
                          const std::function<double(const Pose&)>& score);
/// Candidates search_planar_motion scores for these ranges and steps.
std::size_t planar_grid_size(double range, double step, double yaw_range, double yaw_step);
/// search_planar_motion over long intervals: its grid steps double (from `step`, `yaw_step`)
/// until a level holds at most `max_candidates`, then levels of halving steps around the best
/// come back down to `step`, `yaw_step`; each level's score is `score_for(step)` (a tolerance
/// that follows the step). With a grid that fits at once, this is search_planar_motion.
Pose search_planar_motion_bounded(const Pose& initial, double range, double step, double yaw_range,
                                  double yaw_step, std::size_t max_candidates,
                                  const std::function<std::function<double(const Pose&)>(double)>& score_for);

/// T_coarse between the object sets of the current scan and of the previous one (`target`, built
/// from the previous ObjectSet), starting from `predicted`. Invalid (and equal to `predicted`)
/// with too few matches or when it leaves `gate` around `predicted` (the motion model's gate around
/// its prediction: a jump away from it comes from a few objects registered wrongly, co-moving
/// traffic or repeated posts). No gate: the first scan pair, whose start is a search result.
CoarseResult coarse_motion(const ObjectSet& current, const FeatureMap& target, const Pose& predicted,
                           const PreRegistrationConfig& config, const MotionGate* gate);

}  // namespace dloam
