// The whole configuration of the pipeline: the config structs of the core modules, each declared in
// its module's header and named as in the DLOAM paper (and LeGO-LOAM where the paper defers to it).
// Loaded from / dumped to YAML by dloam/io/config_yaml.hpp; every field has a YAML key of its name.
#pragma once

#include <string>

#include "dloam/core/deskew.hpp"
#include "dloam/core/dynamic_detector.hpp"
#include "dloam/core/features.hpp"
#include "dloam/core/mapping.hpp"
#include "dloam/core/motion_model.hpp"
#include "dloam/core/odometry.hpp"
#include "dloam/core/preregistration.hpp"
#include "dloam/core/segmentation.hpp"
#include "dloam/core/sensor.hpp"

namespace dloam {

/// Every module's configuration (each declared beside its module in core/), one YAML section each.
struct PipelineConfig {
  SensorConfig sensor;
  SegmentationConfig segmentation;
  PreRegistrationConfig preregistration;
  MotionConfig motion;
  DeskewConfig deskew;
  DetectionConfig detection;
  FeatureConfig features;
  OdometryConfig odometry;
  MappingConfig mapping;
  int threads = 2;
};

}  // namespace dloam
