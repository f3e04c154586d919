#include "dloam/eval/map_metrics.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace dloam::eval {

namespace {
constexpr std::int64_t kBias = 1 << 20;
std::uint64_t key_of(std::int64_t x, std::int64_t y, std::int64_t z) {
  return (static_cast<std::uint64_t>(x + kBias) << 42) | (static_cast<std::uint64_t>(y + kBias) << 21) |
         static_cast<std::uint64_t>(z + kBias);
}
bool voxel_of(const Vec3& p, double leaf, std::int64_t v[3]) {
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor(p[a] / leaf);
    if (!std::isfinite(f) || std::abs(f) >= static_cast<double>(kBias - 2)) return false;
    v[a] = static_cast<std::int64_t>(f);
  }
  return true;
}
}  // namespace

double MapAccuracy::sa() const {
  return static_voxels ? static_cast<double>(static_kept) / static_cast<double>(static_voxels)
                       : std::numeric_limits<double>::quiet_NaN();
}
double MapAccuracy::da() const {
  return dynamic_voxels ? 1.0 - static_cast<double>(dynamic_kept) / static_cast<double>(dynamic_voxels)
                        : std::numeric_limits<double>::quiet_NaN();
}
double MapAccuracy::score() const { return std::sqrt(sa() * da()); }

MapAccuracyEvaluator::MapAccuracyEvaluator(const MapAccuracyConfig& config) : config_(config) {
  if (!(config.leaf > 0.0) || !(config.radius > 0.0) || !(config.max_range > 0.0))
    throw InputError("map accuracy: leaf, radius and max_range must be > 0");
  if (config.radius > config.leaf) throw InputError("map accuracy: radius must not exceed the voxel size");
}

void MapAccuracyEvaluator::add_scan(const std::vector<Vec3>& points, const std::vector<Label>& gt,
                                    const Pose& pose) {
  if (points.size() != gt.size())
    throw InputError("map accuracy: " + std::to_string(gt.size()) + " labels for " +
                     std::to_string(points.size()) + " points");
  const double leaf = config_.leaf;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (semantic::is_ignored(gt[i]) || points[i].norm() > config_.max_range) continue;
    const Vec3 w = pose * points[i];
    std::int64_t v[3];
    if (!voxel_of(w, leaf, v)) continue;
    Cell& c = cells_[key_of(v[0], v[1], v[2])];
    for (int a = 0; a < 3; ++a) c.sum[a] += static_cast<float>(w[a] - static_cast<double>(v[a]) * leaf);
    if (semantic::is_moving(gt[i])) {
      ++c.moving_count;
    } else {
      ++c.static_count;
    }
  }
}

MapAccuracy MapAccuracyEvaluator::evaluate(const std::vector<Vec3>& map) const {
  MapAccuracy r;
  const double leaf = config_.leaf, r2 = config_.radius * config_.radius;
  std::unordered_map<std::uint64_t, bool> kept;
  kept.reserve(map.size());
  for (const Vec3& p : map) {
    ++r.map_points;
    std::int64_t v[3];
    if (!voxel_of(p, leaf, v)) {
      ++r.map_unmatched;
      continue;
    }
    double best = r2;
    std::uint64_t best_key = 0;
    const Cell* best_cell = nullptr;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const std::int64_t x = v[0] + dx, y = v[1] + dy, z = v[2] + dz;
          const std::uint64_t k = key_of(x, y, z);
          const auto it = cells_.find(k);
          if (it == cells_.end()) continue;
          const Cell& c = it->second;
          const double n = static_cast<double>(c.static_count + c.moving_count);
          const Vec3 mean(static_cast<double>(x) * leaf + c.sum[0] / n,
                          static_cast<double>(y) * leaf + c.sum[1] / n,
                          static_cast<double>(z) * leaf + c.sum[2] / n);
          const double d2 = (mean - p).squaredNorm();
          if (d2 <= best) {
            best = d2;
            best_key = k;
            best_cell = &c;
          }
        }
    if (!best_cell) {
      ++r.map_unmatched;
      continue;
    }
    const bool dynamic = best_cell->moving_count > best_cell->static_count;
    ++(dynamic ? r.map_dynamic : r.map_static);
    kept[best_key] = true;
  }
  for (const auto& [k, c] : cells_) {
    const bool dynamic = c.moving_count > c.static_count;
    const bool is_kept = kept.count(k) > 0;
    if (dynamic) {
      ++r.dynamic_voxels;
      r.dynamic_kept += is_kept;
    } else {
      ++r.static_voxels;
      r.static_kept += is_kept;
    }
  }
  return r;
}

}  // namespace dloam::eval
