// dloam_node: the DLOAM SLAM pipeline as a ROS 1 node. Parameters (private): ~points_topic,
// ~config (YAML), ~preset, ~out (write `dloam run`'s outputs there on shutdown), ~map_frame,
// ~map_every, ~queue_size. The config's detection.detector picks the moving-object detector (auto: the
// shipped CNN when built with LibTorch). See README.md, "rosbag input and the ROS node".
#include <ros/ros.h>

#include <cstdio>
#include <filesystem>

#include "dloam/io/atomic_file.hpp"
#include "dloam/io/config_yaml.hpp"
#ifdef DLOAM_WITH_TORCH
#include "dloam/cnn/cnn_segmenter.hpp"
#endif
#include "node.hpp"

int main(int argc, char** argv) {
  ros::init(argc, argv, "dloam");
  ros::NodeHandle nh, private_nh("~");
  const auto params = dloam::node::NodeParams::from(private_nh);
  try {
    dloam::PipelineConfig config = dloam::io::config_from(params.preset, params.config);
    if (!params.out.empty()) std::filesystem::create_directories(params.out);
    std::shared_ptr<dloam::MovingSegmenter> cnn;
#ifdef DLOAM_WITH_TORCH
    std::string note;
    cnn = dloam::cnn::prepare_detector(config.detection, DLOAM_MODEL_DIR, config.sensor, &note);
    if (!note.empty()) ROS_WARN("dloam: %s", note.c_str());
#else
    if (config.detection.detector == "auto") config.detection.detector = "geometric";
#endif
    dloam::node::DloamNode node(nh, params, config, cnn);
    ROS_INFO("dloam: %s preset, detector %s; listening on %s", config.sensor.preset.c_str(),
             config.detection.detector.c_str(), params.points_topic.c_str());
    ros::spin();  // returns on shutdown (Ctrl-C, rosnode kill)
    node.write_outputs();
    if (!params.out.empty())  // rosconsole is shut down by now
      std::printf(
          "dloam: %zu scans; wrote poses.txt, poses_tum.txt, map.ply, timing.csv, config.yaml to %s\n",
          node.scans(), params.out.c_str());
  } catch (const std::exception& e) {
    ROS_FATAL("dloam: %s", e.what());
    return 1;
  }
  return 0;
}
