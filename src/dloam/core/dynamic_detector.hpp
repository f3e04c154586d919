// Traditional two-frame dynamic-object detection (paper III.D.3.a): a pixel is static when its
// speed (speed_matrix.hpp, eq. 13) is below v_static; a cluster is dynamic when fewer than alpha
// of its pixels with a known speed are static; pixels uncovered by an occluder that moved away (more
// than v_max behind the previous surface) do not vote. Ground pixels are re-verified: only those with a
// speed below v_ground stay static ground (the others give no feature and do not enter the map).
// Output: per-pixel masks and per-point SemanticKITTI labels (9 static, 251 moving).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dloam/core/enum_names.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/core/speed_matrix.hpp"

namespace dloam {

/// The moving-object detector of a run.
enum class Detector {
  kNone,       ///< no detector (the LeGO-LOAM-style baseline)
  kGeometric,  ///< the two-frame detector (III.D.3.a)
  kCnn,        ///< the multi-frame CNN (III.D.3.b)
  kAuto,       ///< the CNN when a model fits the sensor, else geometric (pipeline/detector_choice.hpp)
};
constexpr std::array<EnumName<Detector>, 4> enum_names(Detector) {
  return {{{Detector::kNone, "none"},
           {Detector::kGeometric, "geometric"},
           {Detector::kCnn, "cnn"},
           {Detector::kAuto, "auto"}}};
}

/// III.D.3 Dynamic-object detection.
struct DetectionConfig {
  /// none | geometric | cnn | auto. auto is resolved before the run (choose_detector).
  Detector detector = Detector::kAuto;
  /// Speeds are eq. 13's range differences after registration and de-skew, divided by the time
  /// between the two scans (m/s): a pixel's threshold in metres is v * dt. The paper's 0.03 / 0.01
  /// m/s (3 / 1 mm at 10 Hz) lie far below the sensor's 2 cm range noise and the de-skew /
  /// registration residuals, so they cannot be used literally: 1 m/s keeps a walking pedestrian
  /// (1.4 m/s) above the threshold and the noise below it at 10 Hz (docs/results.md).
  double v_static = 1.0;  ///< m/s: a pixel is static below this speed
  double v_ground = 1.0;  ///< m/s: ground re-verification threshold
  double alpha = 0.5;     ///< a cluster with less than alpha static points is dynamic
  /// m/s: a pixel whose point lies farther than v_max * dt behind the previous scan's surface does
  /// not vote (disocclusion, dynamic_detector.hpp): 30 m/s is faster than urban traffic. Measured
  /// values: docs/results.md (detector parameters).
  double v_max = 30.0;
  /// Clusters with fewer pixels of known speed are never dynamic (noise). Measured values:
  /// docs/results.md (detector parameters).
  int N_min_dynamic = 40;
  bool pseudo_static = true;  ///< track previous label of objects (stop-and-go)
  /// A tracked dynamic object (dynamic in the last two scans) stays dynamic below this static
  /// fraction. Eq. 13 sees motion only along the rays: a vehicle moving along its own length (passing
  /// beside the sensor) shows a speed only on the pixels its leading end sweeps, about displacement /
  /// visible length of them (0.86 m per scan on a 9 m truck: ~10 %), so its static fraction reaches
  /// ~0.9 while it still moves; a stopped object shows ~0 moving pixels (measured values:
  /// docs/results.md, detector parameters). A pure side view (no end of the object visible) still
  /// loses the object.
  double alpha_tracked = 0.92;
  /// A speed matrix shows motion only relative to T_coarse: when T_coarse brings less than this
  /// fraction of what the recent steps fitted onto the previous scan (a fast turn or a sudden stop
  /// the prediction missed), the static scene itself would look moving, so the scan's detection is
  /// suspended (nothing marked moving; timing.csv `detection_suspended`). The same ratio below which
  /// a step is reported lost. 0: never suspended.
  double min_registration_fit = 0.5;
  // CNN (III.D.3.b)
  int m = 3;                   ///< number of recent speed/residual images in the range-image bag
  std::string model_path;      ///< written by `dloam train`; empty: models/mos_m<m>.pt shipped with dloam
  double cnn_threshold = 0.5;  ///< moving probability threshold
  /// The CNN's forward pass runs on this many column parts of the range image in parallel, each on
  /// one LibTorch thread (cnn/torch_util.hpp, forward_in_parts): one join per scan, no spinning pool.
  int threads = 2;
};

/// Per-cluster speed statistics (index = cluster label, 0 unused).
struct ClusterVotes {
  std::vector<int> known;         ///< pixels with a known speed
  std::vector<int> static_count;  ///< ... of which below v_static
  /// static_count / known, or -1 when fewer than `min_known` pixels have a known speed.
  [[nodiscard]] double static_fraction(int cluster, int min_known) const;
};

/// Pixels of known speed, and those below v_static, per cluster. A pixel whose point lies more than
/// `v_max` behind the previous scan's surface does not vote: no object moves that far in one scan, so
/// the previous scan's surface there was an occluder that has since moved (disocclusion), which says
/// nothing about this point's motion.
ClusterVotes vote_clusters(const SegmentationResult& seg, const SpeedMatrix& S, double v_static,
                           double v_max);

struct DetectionResult {
  std::vector<std::uint8_t> cluster_dynamic;  ///< per cluster label (0..m), 1 = dynamic
  std::vector<double> static_fraction;        ///< per cluster label: static pixels / known, -1 unknown
  std::vector<std::uint8_t> pixel_dynamic;    ///< rows*cols: pixel of a dynamic cluster
  std::vector<std::uint8_t> ground_rejected;  ///< rows*cols: ground pixel with speed >= v_ground
  int num_dynamic = 0;
};

/// The speed thresholds of `config` (m/s) as range changes over an interval of `dt` seconds (m):
/// what detect_dynamic compares the speed matrix with.
DetectionConfig thresholds_over(const DetectionConfig& config, double dt);

/// Cluster decision (fraction of static pixels < alpha; clusters with fewer than N_min_dynamic
/// pixels of known speed stay static) and ground re-verification. The speed thresholds of
/// `config` are in metres over the interval of the speed matrix (thresholds_over).
DetectionResult detect_dynamic(const SegmentationResult& seg, const SpeedMatrix& S,
                               const DetectionConfig& config);

/// Recomputes the pixel mask after cluster_dynamic changed (e.g. by the object tracker).
void update_pixel_mask(const SegmentationResult& seg, DetectionResult& det);

/// Per input point: kMovingGeneric (251) with the cluster id as instance when its pixel belongs to
/// a dynamic cluster, else kStatic (9).
std::vector<Label> point_labels(const SegmentationResult& seg, const DetectionResult& det);

}  // namespace dloam
