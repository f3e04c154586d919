// LiDAR mapping (paper III.G, LeGO-LOAM): scan-to-map registration of the current scan's F_e / F_p
// against the local map of keyframes around the predicted pose, keyframe insertion, loop closure
// (each new keyframe is checked against older ones; an accepted loop optimises the keyframe pose
// graph and moves the keyframes and their global-map points), and the downsampled global map of
// static points (global_map.hpp).
//
// Loop closure runs beside the scans: a keyframe with a loop candidate starts a job (verification,
// pose-graph optimisation, the global map's occupancy at the corrected poses) on its own thread, and
// the first scan at least loop_latency_s later takes its result, waiting for it if need be. Which
// scan takes it depends on scan indices only, so the poses do not depend on thread timing. One loop
// job at a time: keyframes made while one runs, or within loop_min_interval_s after a loop was
// taken, search no loop.
#pragma once

#include <future>
#include <memory>
#include <optional>

#include "dloam/core/global_map.hpp"
#include "dloam/core/local_map.hpp"
#include "dloam/core/loop_closure.hpp"
#include "dloam/core/pose_graph.hpp"

namespace dloam {

/// III.G Mapping: scan-to-map against a local map of keyframes, and loop closure.
struct MappingConfig {
  int every_n_scans = 1;  ///< mapping rate = scan rate / every_n_scans (paper: 2 Hz)
  /// Scan-to-map runs on a worker thread while the odometry goes on: the result for scan k is
  /// integrated at scan k + latency_scans (0: at once, no thread). At most every_n_scans.
  int latency_scans = 1;
  int max_iterations = 15;
  /// An edge's match in the local map is a line when its 5 neighbours spread along it at least this
  /// many times more (variance) than across it. 0: by the sensor, which the Pipeline resolves
  /// (edge_line_ratio_for); a Mapper given 0 takes LOAM's 3. With 3, five map edges scattered
  /// over a wall pass for a line.
  double edge_line_ratio = 0.0;
  double keyframe_distance = 1.0;  ///< m between keyframes
  double keyframe_angle_deg = 10.0;
  double local_map_radius = 50.0;  ///< m around the current pose
  double edge_leaf_size = 0.2;
  double plane_leaf_size = 0.4;
  double map_leaf_size = 0.2;  ///< global map (map.ply) voxel size
  bool loop_closure = true;
  double loop_search_radius = 7.0;
  double loop_min_time_s = 30.0;
  double loop_max_fitness = 0.3;
  /// Loop closure runs beside the scans; its result is taken by the first scan this much later (0:
  /// at once, on the keyframe's own scan).
  double loop_latency_s = 1.5;
  /// After a loop is taken, keyframes search no loop for this long (a street revisited would
  /// otherwise close a loop at nearly every keyframe; each one re-optimises the whole graph).
  double loop_min_interval_s = 5.0;
};

/// `configured` (mapping.edge_line_ratio), or for 0 the measured choice for a sensor of `rows`
/// beams on a `car` or not: 10 on a car from 64 beams up (better on 11 of 14 64-beam car drives),
/// LOAM's 3 otherwise (10 lost a 16-beam open field and two of three 64-beam handheld walks;
/// docs/results.md, "Edge lines in the local map").
double edge_line_ratio_for(double configured, int rows, bool car);

/// The loop parameters of a mapping configuration at a scan rate.
LoopParams loop_params(const MappingConfig& config, double scan_rate_hz);

struct MappingResult {
  Pose pose = Pose::Identity();     ///< refined world pose of the scan (loop-corrected when `loop` is set)
  RegistrationResult registration;  ///< scan-to-map (its degeneracy: directions the map left unconstrained)
  bool keyframe = false;
  std::optional<LoopConstraint> loop;  ///< a loop closed at this scan (then every keyframe pose moved)
};

class Mapper {
 public:
  /// `scan_rate_hz` converts the config's loop_min_time_s to scans (pass SensorConfig::scan_rate_hz).
  /// `degeneracy`: directions of the scan-to-map registration the map does not constrain keep the
  /// predicted pose.
  explicit Mapper(const MappingConfig& config, double scan_rate_hz = 10.0,
                  const DegeneracyConfig& degeneracy = {})
      : config_(config),
        degeneracy_(degeneracy),
        local_(config.local_map_radius, config.edge_leaf_size, config.plane_leaf_size),
        loop_params_(loop_params(config, scan_rate_hz)),
        global_(config.map_leaf_size) {}

  /// Whether a scan at world pose `pose` becomes a keyframe: the first scan does, then one every
  /// keyframe_distance metres or keyframe_angle_deg degrees from the last keyframe.
  [[nodiscard]] bool needs_keyframe(const Pose& pose) const;

  /// Features in the scan's sensor frame; `predicted` world pose from the odometry. `scan` indices
  /// increase. `keyframe`: whether the scan becomes a keyframe (at its registered pose); when not
  /// given, needs_keyframe() of the registered pose decides. `odometry`: the odometry's degeneracy
  /// of the scan in the world frame (second_opinion), asked when degeneracy.odometry_min_features > 0.
  /// `prediction_error`: how far `predicted` can be off; the directions the map leaves
  /// unconstrained keep it only where that is within degeneracy.max_prior_error (zero: all do).
  MappingResult process(std::size_t scan, const FeatureSource& features, const Pose& predicted,
                        std::optional<bool> keyframe = std::nullopt,
                        const std::optional<SecondOpinion>& odometry = std::nullopt,
                        const PriorError& prediction_error = {});

  /// Adds static points (sensor frame) of the newest keyframe's scan to the global map.
  void add_to_global_map(const std::vector<Vec3>& points);
  /// Adds static points of a later scan at world pose `pose` (sensor frame) to the newest
  /// keyframe's share of the global map: they move with that keyframe.
  void add_to_global_map(const std::vector<Vec3>& points, const Pose& pose);
  /// The global map with every keyframe at its current (loop-corrected) pose, one point per voxel.
  [[nodiscard]] std::vector<Vec3> global_map() const;
  /// Keyframes with their current (loop-corrected) poses.
  [[nodiscard]] const std::vector<Keyframe>& keyframes() const { return local_.keyframes(); }
  /// Loops accepted so far, in order.
  [[nodiscard]] const std::vector<LoopConstraint>& loops() const { return loops_; }

  /// Takes the result of a loop job still running (waits for it). Call at the end of a drive, before
  /// keyframes(), loops(), corrected_trajectory() or global_map() are read for good.
  void finish();

  /// Rewrites a trajectory after loop closures. `scan_poses[i]` is the pose reported for scan i (the
  /// `scan` argument of process(), e.g. Pipeline's ScanResult::pose); each scan moves rigidly with the
  /// latest keyframe at or before it, from that keyframe's pose when the scan was reported to its
  /// current one. Scans before the first keyframe are unchanged. Identity when no loop closed.
  [[nodiscard]] std::vector<Pose> corrected_trajectory(const std::vector<Pose>& scan_poses) const;

 private:
  /// What a loop job returns: the loop if verified, then the optimised poses of keyframes 0..k and
  /// the global map's occupancy at them.
  struct LoopOutcome {
    std::optional<LoopConstraint> loop;
    std::vector<Pose> poses;
    GlobalMap::Rebuilt occupancy;
  };
  struct PendingLoop {
    std::size_t due_scan = 0;                        ///< taken by the first scan at or after this
    std::size_t keyframe = 0;                        ///< k, the keyframe that started it
    Pose pose_at_start = Pose::Identity();           ///< keyframe k's pose when it started
    std::unique_ptr<const GlobalMap::Snapshot> map;  ///< read by the job; outlives it (declared first)
    std::future<LoopOutcome> outcome;
  };
  /// From `scan` on, scans were reported with keyframe `keyframe` at `reported`.
  struct Anchor {
    std::size_t scan = 0;
    std::size_t keyframe = 0;
    Pose reported = Pose::Identity();
  };

  /// Graph edge to the newest keyframe, then a loop job when a candidate is near and none runs.
  void start_loop(std::size_t scan);
  /// Takes the pending loop job's result when it is due at `scan` (or `force`): moves the keyframes
  /// and the map, sets out.loop, and keeps the frame change for the next prediction.
  void take_loop(std::size_t scan, bool force, MappingResult* out);

  MappingConfig config_;
  DegeneracyConfig degeneracy_;
  LocalMap local_;
  LoopParams loop_params_;
  std::vector<PoseGraphEdge> edges_;  // odometry edges between consecutive keyframes, loop edges
  std::vector<Anchor> anchors_;       // in scan order
  std::vector<LoopConstraint> loops_;
  GlobalMap global_;
  std::size_t last_scan_ = 0;
  std::size_t no_loop_before_ = 0;      // scan: keyframes before it search no loop (loop_min_interval_s)
  Pose shift_ = Pose::Identity();       // a loop taken since the last prediction moved the world this way
  std::optional<PendingLoop> pending_;  // last: a job still running is waited for before the rest goes
};

}  // namespace dloam
