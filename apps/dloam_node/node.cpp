// dloam_node callbacks and outputs (see node.hpp).
#include "node.hpp"

#include <cstdio>

#include "dloam/ros/pointcloud2.hpp"

#ifdef DLOAM_HAVE_NAV_MSGS
#include <nav_msgs/Odometry.h>
#else
#include <geometry_msgs/PoseStamped.h>
#endif

namespace dloam::node {

namespace {
geometry_msgs::Pose to_msg(const Pose& pose) {
  geometry_msgs::Pose p;
  const Eigen::Quaterniond q(pose.linear());
  p.position.x = pose.translation().x();
  p.position.y = pose.translation().y();
  p.position.z = pose.translation().z();
  p.orientation.x = q.x();
  p.orientation.y = q.y();
  p.orientation.z = q.z();
  p.orientation.w = q.w();
  return p;
}
}  // namespace

NodeParams NodeParams::from(const ::ros::NodeHandle& private_nh) {
  NodeParams p;
  private_nh.param("points_topic", p.points_topic, p.points_topic);
  private_nh.param("config", p.config, p.config);
  private_nh.param("preset", p.preset, p.preset);
  private_nh.param("out", p.out, p.out);
  private_nh.param("map_frame", p.map_frame, p.map_frame);
  private_nh.param("map_every", p.map_every, p.map_every);
  private_nh.param("queue_size", p.queue_size, p.queue_size);
  return p;
}

DloamNode::DloamNode(::ros::NodeHandle& nh, const NodeParams& params, const PipelineConfig& config,
                     std::shared_ptr<MovingSegmenter> cnn)
    : params_(params), pipeline_(config, std::move(cnn)) {
#ifdef DLOAM_HAVE_NAV_MSGS
  odom_pub_ = nh.advertise<nav_msgs::Odometry>("dloam/odometry", 10);
#else
  odom_pub_ = nh.advertise<geometry_msgs::PoseStamped>("dloam/pose", 10);
#endif
  labelled_pub_ = nh.advertise<sensor_msgs::PointCloud2>("dloam/labelled_points", 2);
  map_pub_ = nh.advertise<sensor_msgs::PointCloud2>("dloam/map", 1, /*latch=*/true);
  sub_ = nh.subscribe(params_.points_topic, static_cast<std::uint32_t>(std::max(1, params_.queue_size)),
                      &DloamNode::on_cloud, this);
  if (!params_.out.empty()) {
    run::OutputOptions output;
    output.dir = params_.out;
    outputs_.emplace(output, pipeline_.config());
  }
}

void DloamNode::on_cloud(const sensor_msgs::PointCloud2ConstPtr& msg) {
  const std::size_t index = scans_;
  const std::string where = params_.points_topic + ", message " + std::to_string(index + bad_messages_);
  ScanResult r;
  PointCloud cloud;
  try {
    auto converted = ros1::from_pointcloud2(*msg, where);
    cloud = std::move(converted.cloud);
    if (converted.dropped > 0)
      ROS_DEBUG("%s: %zu NaN/Inf points dropped (is_dense=false)", where.c_str(), converted.dropped);
    // The header stamp is the scan's time: the motion prior, the de-skew and the gaps of scans
    // dropped on the way (a full subscriber queue, a driver under load) follow the real intervals.
    if (!msg->header.stamp.isZero()) cloud.stamp = msg->header.stamp.toSec();
    r = pipeline_.process(cloud);
  } catch (const std::exception& e) {  // a bad message is reported and skipped; the node goes on
    ++bad_messages_;
    ROS_ERROR("dloam: %s", e.what());
    return;
  }
  r.index = index;
  if (r.missed_scans > 0) {  // ROS drops a full queue's oldest messages without a word
    missed_scans_ += static_cast<std::size_t>(r.missed_scans);
    ROS_WARN(
        "dloam: %d scan(s) missing before %s (%.3f s after the previous one; %zu missing so far): "
        "dropped by a full subscriber queue (~queue_size) or upstream",
        r.missed_scans, where.c_str(), r.dt, missed_scans_);
  }
  publish_pose(msg->header, r.pose);
  if (labelled_pub_.getNumSubscribers() > 0) {
    const std::vector<Label> labels =
        r.labels.empty() ? std::vector<Label>(cloud.size(), semantic::kStatic) : r.labels;
    sensor_msgs::PointCloud2 out = ros1::to_pointcloud2(cloud, labels);
    out.header = msg->header;
    labelled_pub_.publish(out);
  }
  if (params_.map_every > 0 && (index + 1) % static_cast<std::size_t>(params_.map_every) == 0)
    publish_map(msg->header.stamp);
  r.stamp = msg->header.stamp.toSec();  // poses_tum.txt: the header stamps
  ROS_DEBUG("dloam: scan %zu in %.1f ms", index, r.times[Module::kTotal]);
  if (outputs_) {  // labels/, moving points, timing, degenerate scans
    const std::string warning = outputs_->add(r, cloud);
    if (!warning.empty()) ROS_WARN("dloam: %s", warning.c_str());
  }
  ++scans_;
}

void DloamNode::publish_pose(const std_msgs::Header& header, const Pose& pose) {
#ifdef DLOAM_HAVE_NAV_MSGS
  nav_msgs::Odometry odom;
  odom.header.stamp = header.stamp;
  odom.header.frame_id = params_.map_frame;
  odom.child_frame_id = header.frame_id;
  odom.pose.pose = to_msg(pose);
  odom_pub_.publish(odom);
#else
  geometry_msgs::PoseStamped stamped;
  stamped.header.stamp = header.stamp;
  stamped.header.frame_id = params_.map_frame;
  stamped.pose = to_msg(pose);
  odom_pub_.publish(stamped);
#endif
#ifdef DLOAM_HAVE_TF2_ROS
  geometry_msgs::TransformStamped tf;
  tf.header.stamp = header.stamp;
  tf.header.frame_id = params_.map_frame;
  tf.child_frame_id = header.frame_id;
  const geometry_msgs::Pose p = to_msg(pose);
  tf.transform.translation.x = p.position.x;
  tf.transform.translation.y = p.position.y;
  tf.transform.translation.z = p.position.z;
  tf.transform.rotation = p.orientation;
  tf_.sendTransform(tf);
#endif
}

void DloamNode::publish_map(const ::ros::Time& stamp) {
  if (map_pub_.getNumSubscribers() == 0) return;
  PointCloud map;
  map.xyz = pipeline_.global_map();
  sensor_msgs::PointCloud2 out = ros1::to_pointcloud2(map);
  out.header.stamp = stamp;
  out.header.frame_id = params_.map_frame;
  map_pub_.publish(out);
}

bool DloamNode::write_outputs() {
  if (!outputs_) return true;
  const run::RunSummary s = outputs_->finish(pipeline_);  // the mapping-refined trajectory, as `dloam run`
  // Called once ros::spin() has returned: rosconsole is shut down, so stdout / stderr.
  for (const auto& problem : s.problems) std::fprintf(stderr, "dloam: error: %s\n", problem.c_str());
  std::printf(
      "dloam: %zu scans, %zu missing in the stamps (dropped before the node or by its full queue), %zu bad "
      "messages skipped; wrote poses.txt, poses_tum.txt, map.ply, moving.ply, timing.csv, config.yaml, "
      "metrics.json to %s\n",
      s.scans, missed_scans_, bad_messages_, params_.out.c_str());
  std::fflush(stdout);
  return s.problems.empty();
}

}  // namespace dloam::node
