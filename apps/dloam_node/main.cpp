// dloam_node: the DLOAM SLAM pipeline as a ROS 1 node. Parameters (private): ~points_topic,
// ~config (YAML), ~preset, ~out (write `dloam run`'s outputs there on shutdown), ~map_frame,
// ~map_every, ~queue_size. The config's detection.detector picks the moving-object detector (auto: the
// shipped CNN when built with LibTorch, found in the data folder). See README.md, "rosbag input and
// the ROS node".
#include <ros/ros.h>

#include <cstdio>

#include "dloam/io/config_yaml.hpp"
#include "dloam/io/data_dir.hpp"
#include "dloam/run/detector_setup.hpp"
#include "dloam/run/process_memory.hpp"
#include "node.hpp"

int main(int argc, char** argv) {
  dloam::run::reuse_freed_memory();
  ros::init(argc, argv, "dloam");
  ros::NodeHandle nh, private_nh("~");
  const auto params = dloam::node::NodeParams::from(private_nh);
  try {
    // ~config: a file, or a configuration shipped in the data folder by name (as `dloam run --config`).
    const std::string config_file =
        params.config.empty() ? "" : dloam::io::resolve_config_file(params.config);
    dloam::PipelineConfig config = dloam::io::config_from(params.preset, config_file);
    std::string note;
    const auto cnn = dloam::run::prepare_detector(config, &note);
    if (!note.empty()) ROS_WARN("dloam: %s", note.c_str());
    dloam::node::DloamNode node(nh, params, config, cnn);
    ROS_INFO("dloam: %s preset, detector %s; listening on %s", config.sensor.preset.c_str(),
             std::string(dloam::name_of(config.detection.detector)).c_str(), params.points_topic.c_str());
    ros::spin();  // returns on shutdown (Ctrl-C, rosnode kill)
    if (!node.write_outputs()) return 1;
  } catch (const std::exception& e) {
    if (ros::isShuttingDown())  // rosconsole is shut down by now
      std::fprintf(stderr, "dloam: error: %s\n", e.what());
    else
      ROS_FATAL("dloam: %s", e.what());
    return 1;
  }
  return 0;
}
