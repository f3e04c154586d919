// The whole configuration of the pipeline: the config structs of the core modules, each declared in
// its module's header and named as in the DLOAM paper (and LeGO-LOAM where the paper defers to it).
// Loaded from / dumped to YAML by dloam/io/config_yaml.hpp; every field has a YAML key of its name.
#pragma once

#include <string>

#include "dloam/core/degeneracy.hpp"
#include "dloam/core/deskew.hpp"
#include "dloam/core/dynamic_detector.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/map_cleaner_config.hpp"
#include "dloam/core/mapping.hpp"
#include "dloam/core/motion_model.hpp"
#include "dloam/core/odometry.hpp"
#include "dloam/core/preregistration.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/core/sensor.hpp"

namespace dloam {

/// How recordings are read (pcap captures, ROS 2 / ROS 1 bags); the command line's --topic,
/// --calibration, --metadata, --returns, --cut-azimuth and --port override these.
struct InputConfig {
  std::string topic;        ///< bag topic; empty: the only PointCloud2 topic, else the only packet topic
  std::string calibration;  ///< Velodyne calibration YAML / Hesai angle CSV; empty: nominal tables
  std::string metadata;     ///< Ouster sensor JSON; empty: the .json of the same name beside the recording
  ReturnMode returns = ReturnMode::kStrongest;  ///< strongest | last | first | all
  double cut_azimuth_deg = 0.0;  ///< a scan ends where the azimuth crosses this (sensor's convention)
  int port = 0;                  ///< pcap: UDP port of the data; 0: the first data packet's
};

/// Every module's configuration (each declared beside its module in core/), one YAML section each.
struct PipelineConfig {
  InputConfig input;
  SensorConfig sensor;
  SegmentationConfig segmentation;
  PreRegistrationConfig preregistration;
  MotionConfig motion;
  DeskewConfig deskew;
  DetectionConfig detection;
  FeatureConfig features;
  OdometryConfig odometry;
  MappingConfig mapping;
  DegeneracyConfig degeneracy;  ///< both registrations: odometry (scan-to-scan) and mapping (scan-to-map)
  MapCleanerConfig clean;       ///< the whole-drive pass (`dloam clean`), not the online pipeline
  int threads = 2;
};

}  // namespace dloam
