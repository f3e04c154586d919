// The whole configuration of the pipeline: one plain struct per module, named as in the
// DLOAM paper (and LeGO-LOAM where the paper defers to it). Loaded from / dumped to YAML by
// dloam/io/config_yaml.hpp; every field here has a YAML key of the same name.
#pragma once

#include <string>

#include "dloam/core/sensor.hpp"

namespace dloam {

/// III.C Segmentation: ground by adjacent-row pitch (eq. 7), range-image clustering.
struct SegmentationConfig {
  double ground_pitch_deg = 10.0;  ///< eq. 7 threshold
  int N_ground_rows = 0;           ///< rows (from the bottom) searched for ground; 0 = beams below -1 deg
  double segment_theta_deg =
      10.0;  ///< angle-based clustering threshold (Bogoslavskyi's 10; LeGO-LOAM's 60 shatters 64-beam scans)
  int N_min_cluster = 30;       ///< clusters with fewer points are outliers (LeGO-LOAM's 30)
  int N_min_cluster_small = 5;  ///< ... unless they have this many points spanning
  int N_min_cluster_rows = 3;   ///< ... at least this many rows
};

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
  /// m: the first scan pair has no motion prior; T_coarse starts from the best forward translation
  /// in [-search_range, search_range] (0: start from identity, as the constant-velocity prior).
  double search_range = 4.0;
  /// Motion gate: a T_coarse that differs from the constant-velocity prediction by more than this
  /// (rotation deg / translation m, per scan) is rejected and the prediction is used instead. At
  /// 10 Hz a vehicle changes its motion per scan by centimetres and tenths of a degree; a larger
  /// jump comes from a few objects registered wrongly (co-moving traffic, repeated posts).
  double max_rotation_change_deg = 1.0;
  double max_translation_change = 0.3;
  /// dloam's addition: T_coarse refined by a projective point-to-plane alignment of the current
  /// scan onto the previous range image (core/range_alignment.hpp). Eq. 13 needs the motion to a
  /// few centimetres; the objects of a 16-beam scan give it to a decimetre and a degree.
  bool refine = true;
};

/// III.D.2 Motion-distortion removal (eq. 12).
struct DeskewConfig {
  bool enabled = true;
  /// "auto": the data's per-point time channel when present, else from the azimuth.
  /// "azimuth": always from the azimuth. "none": no time, no de-skew.
  std::string time_source = "auto";
};

/// III.D.3 Dynamic-object detection.
struct DetectionConfig {
  /// none | geometric | cnn | auto. auto: the CNN when its model file exists (front-ends resolve it
  /// before the run; a Pipeline given no segmenter uses the geometric detector), else geometric.
  std::string detector = "auto";
  /// Speeds are eq. 13's range differences in METRES PER SCAN (x10 = m/s at 10 Hz), after
  /// registration and de-skew. The paper's 0.03 / 0.01 m/s (3 / 1 mm per scan) lie far below the
  /// sensor's 2 cm range noise and the de-skew / registration residuals, so they cannot be used
  /// literally; see the measured choice below.
  /// Measured (100-scan runs): v_static 0.1 / 0.2 / 0.3 m per scan gave MOS IoU 78.1 / 78.4 / 77.0 %
  /// on kitti-raw-0005 and 0.1 / 0.2 gave 54.2 / 44.7 % on a simulated urban drive (slow
  /// pedestrians: 1.4 m/s = 0.14 m per scan), so 0.1 m per scan (1 m/s); v_ground likewise.
  double v_static = 0.1;  ///< a pixel is static below this speed (m per scan)
  double v_ground = 0.1;  ///< ground re-verification threshold (m per scan)
  double alpha = 0.5;     ///< a cluster with less than alpha static points is dynamic
  /// m per scan: a pixel whose point lies farther than this behind the previous scan's surface does
  /// not vote (disocclusion, dynamic_detector.hpp). 3 m per scan = 30 m/s, faster than urban traffic.
  /// Measured (point IoU, off -> 3.0): kitti-raw-0005 82.2 -> 83.0 %, urban seeds 2 / 1 (traffic 3)
  /// / 3 / 7: 84.5 -> 88.7, 60.1 -> 60.3, 50.2 -> 55.2, 45.9 -> 46.9 %; 1.0 to 5.0 changed seeds 1
  /// and 3 by under 2 points.
  double v_max = 3.0;
  /// Clusters with fewer pixels of known speed are never dynamic (noise). Measured (100-scan runs,
  /// point / object IoU): 20 -> 78.0 / 60.7 % on kitti-raw-0005 and 53.9 / 14.4 % on simulated urban
  /// seed 1 traffic 3; 40 -> 78.9 / 76.9 % and 54.8 / 12.9 %.
  int N_min_dynamic = 40;
  bool pseudo_static = true;  ///< track previous label of objects (stop-and-go)
  /// A tracked dynamic object (dynamic in the last two scans) stays dynamic below this static
  /// fraction. Eq. 13 sees motion only along the rays: a vehicle moving along its own length (passing
  /// beside the sensor) shows a speed only on the pixels its leading end sweeps, about displacement /
  /// visible length of them (0.86 m per scan on a 9 m truck: ~10 %), so its static fraction reaches
  /// ~0.9 while it still moves; a stopped object shows ~0 moving pixels. Measured (100-scan runs,
  /// point IoU without v_max; kitti-raw-0005 / urban seed 2 / urban seed 1 traffic 3):
  /// 0.75 -> 82.1 / 56.0 / 59.0 %, 0.90 -> 82.1 / 64.2 / 59.3 %, 0.92 -> 82.2 / 84.5 / 60.1 % (seed 2:
  /// an oncoming truck passing 3 m beside the sensor is kept); with v_max, 0.90 -> 68.0 % on seed 2.
  /// A pure side view (no end of the object visible) still loses the object.
  double alpha_tracked = 0.92;
  // CNN (III.D.3.b)
  int m = 6;                   ///< number of recent speed/residual images in the range-image bag
  std::string model_path;      ///< written by `dloam train`; empty: models/mos_m<m>.pt shipped with dloam
  double cnn_threshold = 0.5;  ///< moving probability threshold
  /// LibTorch threads. 2 on an idle 2-core machine: forward 20 ms instead of 41 ms (bench_cnn). Its
  /// OpenMP pool spins: when other programs load the cores, 1 is much faster (5-20x measured).
  int threads = 2;
};

/// III.E Feature extraction (smoothness eq. 14).
struct FeatureConfig {
  int S = 10;     ///< |S|, neighbours in the same row (half on each side)
  int N_div = 6;  ///< sub-images per row
  int N_fe = 2;   ///< sharpest edges per sub-image row (f_e)
  int N_Fe = 40;  ///< edges per sub-image row (F_e)
  int N_fp = 4;   ///< flattest ground planes per sub-image row (f_p)
  int N_Fp = 80;  ///< (unused cap kept for the paper's name; F_p takes all remaining flat points)
  double c_th =
      0.005;  ///< edge / plane threshold on c (eq. 14 is range-normalised: a 90 deg corner at
              ///< 2048 columns gives c ~ 0.009, 2 cm noise at 5 m ~ 0.004; LeGO's 0.1 is on another scale)
  bool double_pseudo_static = true;  ///< double features in sub-images with type-2 pseudo-static objects
  double plane_leaf_size = 0.2;      ///< voxel size of F_p (less-flat) downsampling
};

/// III.F Odometry: two-step LM (planes -> tz, roll, pitch; edges -> tx, ty, yaw).
struct OdometryConfig {
  int max_iterations = 25;  ///< LM iterations per step
  /// m, nearest-feature search radius. The initial guess is T_coarse or the constant-velocity
  /// prediction, centimetres from the truth; LOAM's 5 m (no prior) lets repeated structure
  /// (fence posts, lamp rows) and unflagged traffic pull the estimate along the road.
  double max_correspondence = 2.0;
  bool weight_compensation = true;  ///< eq. 15
  bool pseudo_static_rejection = true;
  int N_pseudo = 5;   ///< RANSAC iterations of pseudo-static rejection
  double beta = 0.1;  ///< fraction of worst-matching features removed per iteration
  double pseudo_inlier_distance =
      0.1;  ///< m: a feature with a larger residual is an outlier (stop when < beta are)
};

/// III.G Mapping: scan-to-map against a local map of keyframes, and loop closure.
struct MappingConfig {
  int every_n_scans = 1;  ///< mapping rate = scan rate / every_n_scans (paper: 2 Hz)
  /// Scan-to-map runs on a worker thread while the odometry goes on: the result for scan k is
  /// integrated at scan k + latency_scans (0: at once, no thread). At most every_n_scans.
  int latency_scans = 1;
  int max_iterations = 15;
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
};

/// How recordings are read (pcap captures, ROS 2 / ROS 1 bags); the command line's --topic,
/// --calibration, --metadata, --returns, --cut-azimuth and --port override these.
struct InputConfig {
  std::string topic;        ///< bag topic; empty: the only PointCloud2 topic, else the only packet topic
  std::string calibration;  ///< Velodyne calibration YAML / Hesai angle CSV; empty: nominal tables
  std::string metadata;     ///< Ouster sensor JSON; empty: the .json of the same name beside the recording
  std::string returns = "strongest";  ///< strongest | last | first | all
  double cut_azimuth_deg = 0.0;       ///< a scan ends where the azimuth crosses this (sensor's convention)
  int port = 0;                       ///< pcap: UDP port of the data; 0: the first data packet's
};

struct PipelineConfig {
  InputConfig input;
  SensorConfig sensor;
  SegmentationConfig segmentation;
  PreRegistrationConfig preregistration;
  DeskewConfig deskew;
  DetectionConfig detection;
  FeatureConfig features;
  OdometryConfig odometry;
  MappingConfig mapping;
  int threads = 2;
};

}  // namespace dloam
