#include "dloam/core/mapping.hpp"

#include <cmath>

#include "dloam/core/voxel_grid.hpp"

namespace dloam {

MappingResult Mapper::process(std::size_t scan, const FeatureSource& features, const Pose& predicted) {
  MappingResult out;
  out.pose = predicted;
  if (!local_.empty()) {
    RegistrationParams p;
    p.max_iterations = config_.max_iterations;
    p.max_correspondence = 1.0;
    p.dof = kAllDof;
    out.registration = register_features(features, local_.around(predicted.translation()), predicted, p);
    out.pose = out.registration.T;
  }
  // A new keyframe when far enough (or turned enough) from the last one.
  bool add = local_.empty();
  if (!add) {
    const Pose& last = local_.keyframes().back().pose;
    const Pose rel = last.inverse() * out.pose;
    add = rel.translation().norm() >= config_.keyframe_distance ||
          Eigen::AngleAxisd(rel.rotation()).angle() >= config_.keyframe_angle_deg * M_PI / 180.0;
  }
  if (add) {
    local_.add({scan, out.pose, voxel_downsample_points(features.edges, config_.edge_leaf_size),
                voxel_downsample_points(features.planes, config_.plane_leaf_size)});
    out.keyframe = true;
  }
  return out;
}

void Mapper::add_to_global_map(const std::vector<Vec3>& points, const Pose& pose) {
  for (const Vec3& p : voxel_downsample_points(points, config_.map_leaf_size)) global_.push_back(pose * p);
  // Compact when the map has doubled since the last compaction: memory stays bounded by the area.
  if (global_.size() > 2 * compacted_size_ + 1000000) {
    global_ = voxel_downsample_points(global_, config_.map_leaf_size);
    compacted_size_ = global_.size();
  }
}

std::vector<Vec3> Mapper::global_map() const { return voxel_downsample_points(global_, config_.map_leaf_size); }

}  // namespace dloam
