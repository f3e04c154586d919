// The one table of configuration keys: for each struct of dloam/pipeline/config.hpp, a
// visit() listing every field once with its YAML key, a one-line description (paper equation)
// and its allowed range. Loading, dumping and validating the YAML config all walk these
// tables, so adding a parameter is one line here. Internal to dloam_io.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "dloam/pipeline/config.hpp"

namespace dloam::io::detail {

/// Allowed closed range of a number; `lo_open` / `hi_open` exclude the bound.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
};
inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline Range at_least(double lo) { return {lo, kInf, false, false}; }
inline Range above(double lo) { return {lo, kInf, true, false}; }
inline Range within(double lo, double hi) { return {lo, hi, false, false}; }
/// Allowed values of a string; empty = any.
using Choices = std::vector<std::string>;
/// An enumeration field: written and read by the names of its table (core/enum_names.hpp).
struct Named {};
/// Smallest voxel size (m) of any downsampling: the voxel keys are 32-bit integers per axis.
inline constexpr double kMinLeafSize = 0.001;
/// Farthest range (m) a sensor model may keep: no LiDAR measures beyond it.
inline constexpr double kMaxSensorRange = 10000.0;

template <class V>
void visit(InputConfig& c, V& v) {
  v("topic", c.topic, "bag topic; empty: the only PointCloud2 topic, else the only raw-packet topic",
    Choices{});
  v("calibration", c.calibration,
    "Velodyne calibration YAML / Hesai angle CSV; empty: the model's nominal table", Choices{});
  v("metadata", c.metadata,
    "Ouster sensor metadata JSON; empty: the .json of the same name beside the recording", Choices{});
  v("returns", c.returns, "returns kept from multi-return packets: strongest | last | first | all", Named{});
  v("cut_azimuth_deg", c.cut_azimuth_deg,
    "a scan ends where the azimuth crosses this angle (deg, sensor's own)", Range{0, 360, false, true});
  v("port", c.port, "pcap: UDP destination port of the data; 0: the port of the first data packet",
    within(0, 65535));
}

template <class V>
void visit(SensorConfig& c, V& v) {
  v("preset", c.preset,
    "built-in model (dloam config presets), custom (these keys alone) or auto (estimated from the data)",
    Choices{});
  v("N_scan", c.N_scan, "number of beams = range-image rows (eq. 4)", within(2, 512));
  v("Horizon_SCAN", c.Horizon_SCAN, "range-image columns = 2 pi / R_horiz (eq. 5)", within(16, 16384));
  v("beam_elevations_deg", c.beam_elevations_deg,
    "beam elevations (deg), bottom beam first; [] = uniform from Pit_bottom to fov_top", within(-89, 89));
  v("beam_vertical_offsets_m", c.beam_vertical_offsets_m,
    "height of each beam's origin (m), bottom beam first; [] = all 0", within(-1, 1));
  v("Pit_bottom", c.Pit_bottom, "lowest beam pitch (deg), Pit_bottom of eq. 4", within(-90, 90));
  v("fov_top", c.fov_top, "highest beam pitch (deg); R_vert = span / (N_scan - 1)", within(-90, 90));
  v("min_range", c.min_range, "points closer than this (m) are dropped (ego vehicle)",
    within(0, kMaxSensorRange));
  v("max_range", c.max_range, "points farther than this (m) are dropped",
    Range{0, kMaxSensorRange, true, false});
  v("scan_rate_hz", c.scan_rate_hz, "sweeps per second", above(0));
  v("vertical_angle_correction_deg", c.vertical_angle_correction_deg,
    "added to point elevations (deg); KITTI HDL-64E: 0.2-0.25", within(-5, 5));
}

template <class V>
void visit(SegmentationConfig& c, V& v) {
  v("ground_pitch_deg", c.ground_pitch_deg, "ground if adjacent-row pitch Pit_{v,v+1} is below this (eq. 7)",
    Range{0, 90, true, true});
  v("N_ground_rows", c.N_ground_rows, "rows from the bottom searched for ground; 0 = beams below -1 deg",
    within(0, 512));
  v("segment_theta_deg", c.segment_theta_deg, "angle threshold of range-image clustering (LeGO-LOAM)",
    Range{0, 90, true, true});
  v("N_min_cluster", c.N_min_cluster, "clusters with fewer points are outliers (LeGO-LOAM: 30)", at_least(1));
  v("N_min_cluster_small", c.N_min_cluster_small, "... unless they have this many points", at_least(1));
  v("N_min_cluster_rows", c.N_min_cluster_rows, "... spanning at least this many rows", at_least(1));
}

template <class V>
void visit(PreRegistrationConfig& c, V& v) {
  v("enabled", c.enabled, "coarse pre-registration of pole/plane objects (III.D.1)", Range{});
  v("N_PCA", c.N_PCA, "PCA only for clusters with more than N_PCA points", at_least(3));
  v("xi_1", c.xi_1, "pole: normalised lambda_1 above xi_1 (eq. 8)", within(0, 1));
  v("xi_2", c.xi_2, "pole: normalised lambda_2 ~ lambda_3 below xi_2 (eq. 8)", within(0, 1));
  v("xi_3", c.xi_3, "pole: |e_1 . n_ground| above xi_3 (eq. 9)", within(0, 1));
  v("xi_4", c.xi_4, "vertical plane: normalised lambda_3 below xi_4 (eq. 10)", within(0, 1));
  v("xi_5", c.xi_5, "vertical plane: |e_3 . n_ground| below xi_5 (eq. 11)", within(0, 1));
  v("N_coarse", c.N_coarse, "RANSAC iterations of ICP giving T_coarse", at_least(1));
  v("trim_ratio", c.trim_ratio, "worst fraction of ICP matches dropped per iteration",
    Range{0, 1, false, true});
  v("refine", c.refine,
    "refine T_coarse by aligning the two range images (dloam's addition; sparse sensors need it)", Range{});
}

template <class V>
void visit(MotionConfig& c, V& v) {
  v("platform", c.platform, "car | handheld | legged: the defaults of the limits below", Choices{});
  v("max_speed", c.max_speed, "m/s: fastest the sensor moves (the range of a step searched with no prior)",
    above(0));
  v("max_angular_speed_deg", c.max_angular_speed_deg, "deg/s: fastest the sensor turns", above(0));
  v("max_acceleration", c.max_acceleration,
    "m/s^2: velocity change the motion prior admits (an estimate beyond it is not believed)", at_least(0));
  v("max_angular_acceleration_deg", c.max_angular_acceleration_deg,
    "deg/s^2: turn-rate change the motion prior admits", at_least(0));
  v("step_noise", c.step_noise, "m: estimation noise of a step, admitted on top of the accelerations",
    at_least(0));
  v("step_noise_deg", c.step_noise_deg, "deg: the same for rotations", at_least(0));
  v("step_search", c.step_search,
    "search a step without the prediction when the scan contradicts it (and the first step)", Range{});
  v("turn_acceleration", c.turn_acceleration,
    "predict the turn rate about z at constant angular acceleration (a turn from standing), else constant",
    Range{});
}

template <class V>
void visit(DeskewConfig& c, V& v) {
  v("enabled", c.enabled, "de-skew by interpolating T_coarse over the sweep (eq. 12)", Range{});
  v("time_source", c.time_source, "t_i: auto (data's time, else azimuth) | azimuth | none", Named{});
  v("acceleration", c.acceleration,
    "extrapolate the step's velocity to the sweep's reference time with the last velocity change", Range{});
}

template <class V>
void visit(DetectionConfig& c, V& v) {
  v("detector", c.detector,
    "dynamic-object detector: none | geometric | cnn | auto (cnn if the model exists, fits the sensor and "
    "motion.platform is car, else geometric)",
    Named{});
  v("v_static", c.v_static, "m/s: static if the range speed |r_k - r_k-1| / dt (eq. 13) is below this",
    at_least(0));
  v("v_ground", c.v_ground, "m/s: ground re-verification speed threshold (eq. 13)", at_least(0));
  v("alpha", c.alpha, "a cluster with less than alpha static points is dynamic", within(0, 1));
  v("v_max", c.v_max, "m/s: pixels receding faster than this behind the previous surface do not vote",
    at_least(0));
  v("N_min_dynamic", c.N_min_dynamic, "clusters with fewer pixels of known speed stay static", at_least(1));
  v("pseudo_static", c.pseudo_static, "track previous labels of objects (stop-and-go, pseudo-static)",
    Range{});
  v("alpha_tracked", c.alpha_tracked, "a tracked dynamic object stays dynamic below this static fraction",
    within(0, 1));
  v("min_registration_fit", c.min_registration_fit,
    "suspend the scan's detection when T_coarse fits less than this fraction of what recent steps fitted",
    within(0, 1));
  v("m", c.m, "CNN: number of recent speed images in the range image bag", within(0, 64));
  v("model_path", c.model_path,
    "CNN: model written by `dloam train` (empty: models/mos_m<m>.pt shipped with dloam)", Choices{});
  v("cnn_threshold", c.cnn_threshold, "CNN: moving-probability threshold", within(0, 1));
  v("threads", c.threads,
    "CNN inference: column parts of the range image run in parallel (one LibTorch thread each)",
    within(1, 256));
}

template <class V>
void visit(FeatureConfig& c, V& v) {
  v("S", c.S, "|S|: same-row neighbours of c_i (eq. 14), half per side", within(2, 100));
  v("N_div", c.N_div, "sub-images per range-image row", within(1, 360));
  v("N_fe", c.N_fe, "sharpest edges per sub-image row (f_e)", at_least(0));
  v("N_Fe", c.N_Fe, "edges per sub-image row (F_e)", at_least(0));
  v("N_fp", c.N_fp, "flattest ground planes per sub-image row (f_p)", at_least(0));
  v("N_Fp", c.N_Fp, "cap named in the paper; F_p takes all remaining flat points", at_least(0));
  v("c_th", c.c_th, "edge if c_i > c_th, plane if below (eq. 14)", above(0));
  v("double_pseudo_static", c.double_pseudo_static,
    "double features in sub-images with type-2 pseudo-static "
    "objects",
    Range{});
  v("plane_leaf_size", c.plane_leaf_size, "voxel size (m) of F_p downsampling", above(0));
}

template <class V>
void visit(OdometryConfig& c, V& v) {
  v("max_iterations", c.max_iterations, "LM iterations per step (planes: tz roll pitch; edges: tx ty yaw)",
    at_least(1));
  v("max_correspondence", c.max_correspondence, "nearest-feature search radius (m) around the initial guess",
    above(0));
  v("edge_line_ratio", c.edge_line_ratio,
    "an edge's 5 neighbours in the previous scan are a line when their variance along it is this many times "
    "that across (LOAM: 3)",
    at_least(1));
  v("max_level_tilt_deg", c.max_level_tilt_deg,
    "deg: a sensor tilted more than this from level is registered in all 6 DoF at once (no two-step LM)",
    within(0, 90));
  v("weight_compensation", c.weight_compensation, "weight features by s_i (1 - r_horiz / |theta|) (eq. 15)",
    Range{});
  v("pseudo_static_rejection", c.pseudo_static_rejection, "RANSAC rejection of pseudo-static features",
    Range{});
  v("N_pseudo", c.N_pseudo, "RANSAC iterations of pseudo-static rejection", at_least(1));
  v("beta", c.beta, "fraction of worst-matching features removed per iteration", Range{0, 1, false, true});
  v("pseudo_inlier_distance", c.pseudo_inlier_distance,
    "pseudo-static rejection: a feature matching worse than this (m) is an outlier", above(0));
}

template <class V>
void visit(DegeneracyConfig& c, V& v) {
  v("min_features", c.min_features,
    "a direction of motion constrained by less than this many features' worth of residual keeps the prior",
    at_least(0));
  v("min_fraction", c.min_fraction,
    "... or by less than this share of the matched features' worth (both 0: never degenerate)", within(0, 1));
  v("rotation_radius", c.rotation_radius,
    "m: rotations count as the displacement they cause at this distance", above(0));
  v("max_prior_error", c.max_prior_error,
    "m: ... only where the prior can be off by less than this (the motion gate, rotations at "
    "rotation_radius)",
    at_least(0));
  v("odometry_min_features", c.odometry_min_features,
    "scan-to-map: a translation only min_fraction leaves unconstrained is estimated where the odometry "
    "constrains it by this many features' worth (0: never)",
    at_least(0));
}

template <class V>
void visit(MappingConfig& c, V& v) {
  v("every_n_scans", c.every_n_scans, "mapping rate = scan rate / every_n_scans (paper: 2 Hz)", at_least(1));
  v("latency_scans", c.latency_scans,
    "scan-to-map runs in parallel; its result is used this many scans later (0: at once, <= every_n_scans)",
    at_least(0));
  v("max_iterations", c.max_iterations, "LM iterations of scan-to-map matching", at_least(1));
  v("edge_line_ratio", c.edge_line_ratio,
    "an edge's 5 local-map neighbours are a line when their variance along it is this many times that across "
    "(LOAM: 3; 0: 10 on a car with 64 beams or more, else 3)",
    at_least(0));
  v("keyframe_distance", c.keyframe_distance, "m between keyframes", at_least(0));
  v("keyframe_angle_deg", c.keyframe_angle_deg, "deg between keyframes", at_least(0));
  v("local_map_radius", c.local_map_radius, "local map: keyframes within this radius (m)", above(0));
  v("edge_leaf_size", c.edge_leaf_size, "voxel size (m) of local-map edges", above(0));
  v("plane_leaf_size", c.plane_leaf_size, "voxel size (m) of local-map planes", above(0));
  v("map_leaf_size", c.map_leaf_size, "voxel size (m) of the global map (map.ply)", above(0));
  v("loop_closure", c.loop_closure, "search loop closures among past keyframes", Range{});
  v("loop_search_radius", c.loop_search_radius, "loop candidates within this distance (m)", above(0));
  v("loop_min_time_s", c.loop_min_time_s, "... and at least this much older (s)", at_least(0));
  v("loop_max_fitness", c.loop_max_fitness, "accept a loop when ICP fitness is below this", above(0));
  v("loop_latency_s", c.loop_latency_s,
    "s: loop closure runs beside the scans; the first scan this much later takes its result (0: at once)",
    at_least(0));
  v("loop_min_interval_s", c.loop_min_interval_s, "s after a loop is taken during which no loop is searched",
    at_least(0));
}

template <class V>
void visit(MapCleanerConfig& c, V& v) {
  v("label_window", c.label_window, "scans on each side whose views decide the per-scan labels", at_least(1));
  v("map_window", c.map_window, "scans on each side whose views decide what enters the map (>= label_window)",
    at_least(1));
  v("map_stride", c.map_stride, "beyond the label window, every N-th scan of the map window views",
    at_least(1));
  v("max_view_distance", c.max_view_distance, "viewers farther than this from the scan are skipped (m)",
    above(0));
  v("max_range", c.max_range, "points farther than this from a viewer get no evidence from it (m)", above(0));
  v("margin", c.margin, "seen through: every nearby return farther than the point by this (m) ...",
    at_least(0));
  v("margin_per_m", c.margin_per_m, "... plus this per metre of range (also widens occupied_tolerance)",
    at_least(0));
  v("occupied_tolerance", c.occupied_tolerance, "seen occupied: a nearby return within this of the range (m)",
    above(0));
  v("ground_clearance", c.ground_clearance,
    "no seen-through evidence for points this close to a ground plane (grazing rays, m)", at_least(0));
  v("neighbour_rows", c.neighbour_rows, "pixel neighbourhood checked: +-rows", at_least(0));
  v("neighbour_cols", c.neighbour_cols, "pixel neighbourhood checked: +-columns", at_least(0));
  v("moving_fraction", c.moving_fraction,
    "a cluster is moving when more than this fraction of its points with evidence are seen through",
    Range{0, 1, true, true});
  v("min_moving_points", c.min_moving_points, "... and at least this many", at_least(1));
  v("map_min_free", c.map_min_free, "map: a point's place is empty when at least this many views ...",
    at_least(1));
  v("map_point_fraction", c.map_point_fraction,
    "... and this share of the time it was seen (views weighted by the scans they stand for) saw through it",
    Range{0, 1, true, false});
  v("map_fraction", c.map_fraction,
    "more than this fraction of a cluster's points seen empty keeps it out of the map",
    Range{0, 1, true, true});
  v("min_map_points", c.min_map_points, "... with at least this many points", at_least(1));
  v("far_point_stride", c.far_point_stride, "beyond the label window, every N-th point is checked",
    at_least(1));
  v("map_leaf_size", c.map_leaf_size, "voxel size of the cleaned map (m)", above(0));
  v("map_ground_dilation", c.map_ground_dilation,
    "ground and unclustered pixels within this many pixels of a removed object stay out of the cleaned map",
    at_least(0));
  v("map_max_range", c.map_max_range,
    "points farther than this from their scan stay out of the cleaned map (m)", above(0));
}

/// Top level: one group per module, then the shared thread count.
template <class V>
void visit(PipelineConfig& c, V& v) {
  v.group("input", c.input, "recordings (pcap, ROS 2 / ROS 1 bags): topic, calibration, returns");
  v.group("sensor", c.sensor, "LiDAR model: range-image projection (eqs. 4-6)");
  v.group("segmentation", c.segmentation, "III.C ground extraction (eq. 7) and clustering");
  v.group("preregistration", c.preregistration, "III.D.1 PCA pole/plane pre-registration (eqs. 8-11)");
  v.group("motion", c.motion, "motion prior and gates in physical units (platform limits)");
  v.group("deskew", c.deskew, "III.D.2 motion-distortion removal (eq. 12)");
  v.group("detection", c.detection, "III.D.3 dynamic-object detection (eq. 13)");
  v.group("features", c.features, "III.E feature extraction (eq. 14)");
  v.group("odometry", c.odometry, "III.F two-step LM odometry (eq. 15)");
  v.group("mapping", c.mapping, "III.G scan-to-map mapping and loop closure");
  v.group("degeneracy", c.degeneracy,
          "directions the features do not constrain keep the motion prior (odometry and mapping)");
  v.group("clean", c.clean,
          "the whole-drive pass (dloam clean): range-image visibility, both directions in time");
  v("threads", c.threads, "worker threads of the pipeline", within(1, 256));
}

}  // namespace dloam::io::detail
