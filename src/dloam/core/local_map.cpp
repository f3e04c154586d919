#include "dloam/core/local_map.hpp"

#include <algorithm>

namespace dloam {

namespace {
std::size_t feature_count(const Keyframe& kf) { return kf.edges.size() + kf.planes.size(); }
}  // namespace

void LocalMap::insert(std::size_t keyframe) {
  const Keyframe& kf = keyframes_[keyframe];
  std::vector<Vec3> world;
  world.reserve(std::max(kf.edges.size(), kf.planes.size()));
  for (const Vec3& p : kf.edges) world.push_back(kf.pose * p);
  edges_.add(world);
  world.clear();
  for (const Vec3& p : kf.planes) world.push_back(kf.pose * p);
  planes_.add(world);
  in_map_[keyframe] = true;
  map_input_ += feature_count(kf);
}

const FeatureMap& LocalMap::around(const Vec3& position) {
  // Members: keyframes within the radius, plus the last few (always relevant, even when turning).
  std::vector<std::size_t> members;
  const std::size_t n = keyframes_.size();
  constexpr std::size_t kRecent = 10;
  for (std::size_t i = 0; i < n; ++i) {
    const bool recent = i + kRecent >= n;
    if (recent || (keyframes_[i].pose.translation() - position).norm() < radius_) members.push_back(i);
  }
  if (!dirty_ && members == members_) return map_;
  members_ = std::move(members);
  in_map_.resize(n, false);

  // Features in the map of keyframes that are no longer members: past a third of the map's
  // input, rebuild (they only add far-away points, but they would grow the map without bound).
  std::size_t members_in_map = 0;
  for (std::size_t i : members_)
    if (in_map_[i]) members_in_map += feature_count(keyframes_[i]);
  const bool rebuild = dirty_ || 3 * (map_input_ - members_in_map) > map_input_;
  bool added = rebuild;
  if (rebuild) {
    edges_.clear();
    planes_.clear();
    std::fill(in_map_.begin(), in_map_.end(), false);
    map_input_ = 0;
    ++rebuilds_;
    dirty_ = false;
  }
  for (std::size_t i : members_)
    if (!in_map_[i]) insert(i), added = true;
  // A keyframe that only left changes nothing; a new one rebuilds the k-d trees.
  if (added) {
    map_.edges.build(edges_.points());
    map_.planes.build(planes_.points());
  }
  return map_;
}

}  // namespace dloam
