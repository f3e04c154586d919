// dloam_node: runs the DLOAM pipeline on each sensor_msgs/PointCloud2 message of a topic and
// publishes the pose (nav_msgs/Odometry, or geometry_msgs/PoseStamped without nav_msgs), the TF
// map -> sensor frame, the scan with a per-point static/moving `label`, and the global map.
#pragma once

#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dloam/pipeline/pipeline.hpp"
#include "dloam/run/run_outputs.hpp"

#ifdef DLOAM_HAVE_TF2_ROS
#include <tf2_ros/transform_broadcaster.h>
#endif

namespace dloam::node {

/// Private parameters (~name) of the node.
struct NodeParams {
  std::string points_topic = "/velodyne_points";
  std::string config;  ///< YAML file (see `dloam config dump`); empty: defaults + preset
  std::string preset;  ///< sensor preset (HDL-64E when empty and no config)
  std::string out;     ///< folder for `dloam run`'s outputs, written on shutdown; empty: none
  std::string map_frame = "map";
  int map_every = 10;  ///< publish the global map every N scans (0: never)
  int queue_size = 5;
  static NodeParams from(const ::ros::NodeHandle& private_nh);
};

class DloamNode {
 public:
  DloamNode(::ros::NodeHandle& nh, const NodeParams& params, const PipelineConfig& config,
            std::shared_ptr<MovingSegmenter> cnn = nullptr);
  /// The output folder of `dloam run` (run/run_outputs.hpp) in params.out: poses.txt (KITTI, sensor
  /// frame), poses_tum.txt (header stamps), map.ply, moving.ply, timing.csv, config.yaml,
  /// metrics.json (labels/ are written per scan). Prints what it wrote, with the scans dropped;
  /// false when a file could not be written.
  bool write_outputs();
  [[nodiscard]] std::size_t scans() const { return scans_; }

 private:
  void on_cloud(const sensor_msgs::PointCloud2ConstPtr& msg);
  void publish_pose(const std_msgs::Header& header, const Pose& pose);
  void publish_map(const ::ros::Time& stamp);

  NodeParams params_;
  Pipeline pipeline_;
  ::ros::Subscriber sub_;
  ::ros::Publisher odom_pub_, labelled_pub_, map_pub_;
#ifdef DLOAM_HAVE_TF2_ROS
  tf2_ros::TransformBroadcaster tf_;
#endif
  std::optional<run::RunOutputs> outputs_;  ///< when params.out is given
  std::size_t scans_ = 0;
  std::size_t bad_messages_ = 0;
  std::size_t missed_scans_ = 0;  ///< scans missing between the stamps of consecutive messages
};

}  // namespace dloam::node
