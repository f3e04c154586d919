// The DLOAM pipeline (paper Fig. 1): segmentation -> (pre-registration, de-skew) -> dynamic-object
// detection -> feature extraction from static points -> scan-to-scan odometry -> scan-to-map
// mapping -> transform integration. One call per scan, in order; deterministic.
// Mapping runs in parallel (LOAM / LeGO-LOAM transform integration): the scan-to-map job of scan k
// runs on a worker thread while the next scans' odometry goes on, and its correction is
// integrated at the fixed scan k + mapping.latency_scans, so the poses do not depend on thread
// timing. Loop closure runs on a thread of its own in the same way (Mapper, mapping.loop_latency_s).
// The first scan is de-skewed retroactively once the first motion is known (scan 1).
#pragma once

#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "dloam/core/features.hpp"
#include "dloam/core/mapping.hpp"
#include "dloam/core/moving_segmenter.hpp"
#include "dloam/core/odometry.hpp"
#include "dloam/core/step_search.hpp"
#include "dloam/core/types.hpp"
#include "dloam/pipeline/config.hpp"
#include "dloam/pipeline/dynamic_stage.hpp"
#include "dloam/pipeline/timing.hpp"

namespace dloam {

struct ScanResult {
  std::size_t index = 0;
  double stamp = 0.0;    ///< s: the scan's stamp, or its index times the sweep duration when it has none
  double dt = 0.0;       ///< s since the previous scan (0 for the first)
  int missed_scans = 0;  ///< sweeps between the previous scan and this one that are not in the data
  Pose pose = Pose::Identity();             ///< integrated world pose (sensor frame at mid-sweep)
  Pose odometry_pose = Pose::Identity();    ///< odometry-only pose
  std::vector<Label> labels;                ///< per input point: 9 static / 251 moving (detector on)
  std::vector<std::size_t> edge_features;   ///< input point indices of F_e
  std::vector<std::size_t> plane_features;  ///< input point indices of F_p
  std::size_t n_edges = 0, n_planes = 0;    ///< |F_e|, |F_p|
  std::vector<std::size_t> map_points;      ///< input indices of the points added to the global map
  bool mapped = false;                      ///< a scan-to-map job was started for this scan
  bool keyframe = false;                    ///< ... and the scan becomes a keyframe
  bool loop_closed = false;  ///< a loop-closure correction was integrated at this scan (pose jump)
  /// Some direction of the scan's motion is not constrained by its features against the previous
  /// scan's (the smallest eigenvalue of the odometry's normal matrix below
  /// degeneracy.min_features, or too few features): the motion prior was kept along it.
  bool degenerate = false;
  Degeneracy degeneracy;  ///< of the scan-to-scan odometry (all features, six degrees of freedom)
  /// Of the scan-to-map registration integrated at this scan (the job of scan index -
  /// mapping.latency_scans, see times[kMapping]); free == 0 when none was integrated.
  Degeneracy map_degeneracy;
  /// The step check (the prediction against the previous scan's surfaces, see Pipeline::process):
  /// fraction of the probe points that fit with the prediction and with the final estimate.
  double prior_fitness = 0.0, fitness = 0.0;
  std::size_t search_candidates = 0;  ///< > 0: the step was searched without the prediction
  bool reinitialized = false;         ///< the search replaced a prediction the data contradicted
  bool lost = false;                  ///< the step could not be estimated (fits far worse than recent steps)
  int num_dynamic = 0;                ///< dynamic clusters (detector on)
  int pseudo_static = 0;              ///< type-2 pseudo-static objects (dynamic -> static)
  bool coarse_valid = false;          ///< pre-registration gave T_coarse
  bool detection_suspended = false;   ///< T_coarse fitted too poorly to trust a speed matrix (no detection)
  std::size_t rejected_features = 0;  ///< removed by the pseudo-static rejection
  /// Per module (ms); kMapping: duration of the mapping job integrated at this scan (it ran on
  /// the worker thread); kTotal: this call's wall time, including any wait for that job.
  ModuleTimes times;
};

class Pipeline {
 public:
  /// `cnn`: the learned moving-object segmenter, required when detection.detector is cnn
  /// (dloam/run/detector_setup.hpp resolves auto and loads it); auto is resolved with
  /// choose_detector (a segmenter given counts as fitting the sensor).
  explicit Pipeline(const PipelineConfig& config, std::shared_ptr<MovingSegmenter> cnn = nullptr);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;  // a mapping job may hold `this`
  Pipeline& operator=(const Pipeline&) = delete;

  /// `pose` of the result: the real-time integrated pose (odometry with the latest mapping
  /// correction integrated so far).
  ScanResult process(const PointCloud& cloud);
  /// Waits for the mapping job in flight and integrates it (the accessors below call it).
  void finish();

  [[nodiscard]] const PipelineConfig& config() const { return config_; }
  /// The global map, every keyframe's points at its current (loop-corrected) pose.
  [[nodiscard]] std::vector<Vec3> global_map();
  /// The best estimate of every scan's pose so far: the odometry with the correction of the latest
  /// mapped scan at or before it (the mapped pose itself for mapped scans), moved with its
  /// keyframe after loop closures. Write this trajectory; `ScanResult::pose` is the real-time one.
  [[nodiscard]] std::vector<Pose> trajectory();
  /// The poses reported so far (`ScanResult::pose`, one per scan in order), each moved with its
  /// keyframe when a loop closure corrected the keyframes afterwards.
  [[nodiscard]] std::vector<Pose> corrected_trajectory(const std::vector<Pose>& reported) {
    finish();
    return mapper_.corrected_trajectory(reported);
  }
  [[nodiscard]] std::size_t loop_closures() {
    finish();
    return mapper_.loops().size();
  }

 private:
  /// What the mapping job of a scan needs; built on the main thread.
  struct MappingInput {
    std::size_t scan = 0;
    FeatureSource features;    ///< F_e, F_p (sensor frame)
    std::vector<Vec3> points;  ///< static points for the global map (keyframes only)
    Pose predicted = Pose::Identity();
    bool keyframe = false;
    std::optional<SecondOpinion> odometry;  ///< the odometry's degeneracy, world frame
    PriorError prediction_error;            ///< how far `predicted` can be off (zero: not known)
  };
  struct MappingOutput {
    MappingResult result;
    double ms = 0.0;
  };
  /// The first scan, kept until the first motion de-skews it.
  struct FirstScan {
    std::vector<Vec3> raw;  ///< empty when there is no de-skew
    std::vector<double> times;
    std::vector<int> F_e_index, F_p_index;
    std::vector<std::size_t> map_points;
    MappingInput input;  ///< as extracted (not de-skewed)
  };

  /// Mapping section of process(): join the due job, start this scan's job.
  void map_scan(ScanResult& out, const FeatureSet& features, const std::vector<Vec3>& points,
                std::vector<std::size_t> map_points, const std::vector<Vec3>& raw,
                const std::vector<double>& times);
  void start_job(MappingInput input);
  /// Joins the job in flight and integrates its correction (transform integration).
  void integrate_job(ScanResult* out);
  /// Scan 1: de-skews the first scan's features (the odometry target) and map points with the
  /// sweep motion of scan 1 (constant velocity): T_coarse before the first estimate, then the
  /// estimate; map_scan() then maps it.
  void deskew_first_scan(const SweepMotion& sweep_motion);
  /// The time since the previous scan from the stamps (one sweep when a stamp is missing).
  ScanInterval interval_of(const PointCloud& cloud, ScanResult& out);
  /// The fraction of the surface of the `probe` pixels whose range agrees with the previous
  /// range image (its static part) within `tolerance` (m) after the motion T.
  [[nodiscard]] double consistency(const SegmentationResult& seg, const std::vector<Vec3>& points,
                                   const std::vector<int>& probe, const Pose& T, double tolerance) const;
  /// Checks the prediction of `prior` and, when it does not fit (or there is no velocity yet),
  /// replaces it by the result of a search that does not assume it. True when it was replaced.
  bool check_prior(StepPrior& prior, const SegmentationResult& seg, const std::vector<Vec3>& points,
                   const std::vector<int>& probe, ScanResult& out);

  PipelineConfig config_;
  ScanToScanOdometry odometry_;
  Mapper mapper_;
  std::unique_ptr<DynamicStage> dynamic_;  ///< geometric detector, when on
  std::size_t count_ = 0;
  Pose odometry_pose_ = Pose::Identity();
  Pose correction_ = Pose::Identity();  ///< mapping pose * odometry pose^-1 (transform integration)
  Pose last_pose_ = Pose::Identity();
  MotionModel motion_;  ///< the constant-velocity prior, in physical units
  std::optional<double> last_stamp_;
  double previous_dt_ = 0.0;           ///< s between the previous scan and the one before (0: none)
  std::vector<float> previous_range_;  ///< the previous scan's range image
  double fit_reference_ = 0.0;         ///< what recent estimates fit (running mean)
  std::vector<Pose> odometry_poses_;   ///< per scan
  std::vector<std::pair<std::size_t, Pose>> mapped_;  ///< (scan, refined pose) of integrated jobs
  std::optional<FirstScan> first_;
  bool keyframe_without_points_ = false;  ///< the newest keyframe's scan added no map points
  struct Job {
    std::size_t scan = 0;
    Pose odometry_pose = Pose::Identity();
    std::future<MappingOutput> output;
  };
  std::optional<Job> job_;  ///< last member: destroyed (joined) first
};

}  // namespace dloam
